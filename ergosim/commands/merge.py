"""``ergosim merge DIR... --out OUT``: join shards of one run (``ergosim run --subject-range A:B``).

The statistics are recomputed from the shards' subject records, so shards that cover every subject give
the unsharded run's summary.json byte for byte. Exit status: 0 merged, 2 bad input (shards of different
runs, overlapping or missing subjects, an unfinished shard), 3 merged but a repetition was abandoned.
"""

from __future__ import annotations

import argparse
from pathlib import Path

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "merge", help="merge shards of one run (ergosim run --subject-range) into one run folder",
        description="Merge the run folders of shards of one run (same scenario, seed and protocol, disjoint "
                    "subject ranges) into --out, recomputing summary.json and the CSVs from the shards' "
                    "subject_records.json.",
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="run folders written by ergosim run")
    p.add_argument("--out", required=True, help="the merged run folder (not one of the shards)")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="print only where the results are; log warnings only")
    return p


def run(args) -> int:
    from ergosim.experiment.protocol import protocol_from_record  # noqa: PLC0415
    from ergosim.experiment.run_merge import merge_runs  # noqa: PLC0415 - keep `ergosim --help` fast
    from ergosim.experiment.scenario_run import EXIT_ABANDONED  # noqa: PLC0415
    from ergosim.experiment.summary_text import summary_text  # noqa: PLC0415

    result = merge_runs([Path(d) for d in args.dirs], Path(args.out))
    if not args.quiet:
        cfg = protocol_from_record({k: v for k, v in result.config.items() if k != "overrides"})
        print(summary_text(result.summary, cfg))
    first, last = result.subjects.start, result.subjects.stop - 1
    print(f"merged {len(args.dirs)} run folder(s), subjects {first}..{last}: {result.out.resolve()}")
    return EXIT_ABANDONED if result.summary["status"] == "abandoned" else 0
