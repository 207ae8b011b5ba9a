"""Calibrate the workers' pace against the paper's timing facts (§7.1 Table 1, §7.2 H only within the takt).

    python scripts/calibrate_pace.py [--paces 0.15,0.2,...] [--seeds 5] [--json PATH]

§7.1: prints, per pace, the repetition of the first robot decision of each seed, and the calibrated pace (the
geometric middle of the paces where most seeds first call the robot in rp2). §7.2: the slowest H-only
repetition at MTM-1 standard pace over seeds 0-2 and the band it leaves. The logic and its rationale live in
ergosim.fidelity.pace; the results are the ``pace`` of ergosim/data/scenarios/kwear-validation.toml and
multi-subject.toml.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from ergosim.atomic import write_json
from ergosim.fidelity.pace import calibrated_pace, h_only_band, pace_scan


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paces", default="0.15,0.2,0.25,0.3,0.35,0.4,0.5,0.6")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--json", metavar="PATH")
    args = parser.parse_args(argv)
    paces = [float(p) for p in args.paces.split(",")]
    rows = pace_scan(paces, range(args.seeds), log=lambda msg: print(msg, flush=True))
    pace = calibrated_pace(rows)
    print(f"§7.1 calibrated pace: {pace:.3f}" if pace else "§7.1: no pace calls the robot first in rp2")
    low, high, ms_pace = h_only_band(range(3), log=lambda msg: print(msg, flush=True))
    print(f"§7.2: H only within the takt allows paces {low:.3f}-{high:.3f}; calibrated pace {ms_pace:.3f}")
    if args.json:
        write_json(args.json, {"rows": [dataclasses.asdict(r) | {"first_robot": {str(k): v for k, v in
                                                                                 r.first_robot.items()}}
                                        for r in rows], "calibrated_pace": pace,
                               "multi_subject": {"band": [low, high], "calibrated_pace": ms_pace}})
    return 0


if __name__ == "__main__":
    sys.exit(main())
