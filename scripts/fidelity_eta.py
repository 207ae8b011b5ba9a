"""§7.2's calibration fact (η = 3 executions ensured Ṽ < 1e-3) against the twin, over the suit's error and
the subjects' trial-to-trial variability.

    python scripts/fidelity_eta.py [--noise 1,0.5,0.25,0.1,0] [--variability 1,0.5,0.25,0] [--subjects 12]
                                   [--seeds 0] [--json PATH]

Scans the suit's error (``noise_scale``) at the subjects' own variability, then the variability without
the suit's error. The logic lives in ergosim.fidelity.calibration_eta; docs/fidelity.md has the figures.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from ergosim.atomic import write_json
from ergosim.fidelity.calibration_eta import allowed_band, eta_scan


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--noise", default="1,0.5,0.25,0.1,0")
    parser.add_argument("--variability", default="0.5,0.25,0.1")
    parser.add_argument("--subjects", type=int, default=12)
    parser.add_argument("--seeds", default="0")
    parser.add_argument("--json", metavar="PATH")
    args = parser.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    say = lambda msg: print(msg, flush=True)  # noqa: E731
    noise = eta_scan([(float(k), 1.0) for k in args.noise.split(",")], seeds, subjects=args.subjects, log=say)
    var = eta_scan([(0.0, float(f)) for f in args.variability.split(",")], seeds, subjects=args.subjects,
                   log=say)
    quiet = [r for r in noise if r.noise_scale == 0]  # no suit error, the subjects' own variability
    for lever, rows in (("noise_scale", noise), ("variability", var + quiet)):
        band = allowed_band(rows, lever)
        print(f"{lever}: the fact holds for {lever} in [{band[0]:g}, {band[1]:g}]" if band else
              f"{lever}: the fact holds at no scanned {lever}")
    if args.json:
        write_json(args.json, {"rows": [dataclasses.asdict(r) for r in noise + var]})
    return 0


if __name__ == "__main__":
    sys.exit(main())
