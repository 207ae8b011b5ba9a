"""The robot-only assembly of a scenario (paper §7.2 set the takt from it): per-action robot times.

    python scripts/robot_timing.py [--scenario multi-subject] [--subjects 3] [--seed 0] [--set K=V ...]
                                   [--sensitivity] [--json PATH]

Runs one r-only repetition per subject in the real loop and prints, per action, its duration and the
robot's transit, contact-critical, gripper, waiting-at-the-handover and way-home times.
``--sensitivity`` repeats it with the transit speed at -10 % and +10 %. The logic lives in
ergosim.experiment.robot_timing.
"""

from __future__ import annotations

import argparse

from ergosim.atomic import write_json
from ergosim.experiment.robot_timing import format_summary, robot_only_runs, timing_summary
from ergosim.experiment.scenario import load_scenario
from ergosim.overrides import parse_assignments


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="multi-subject")
    parser.add_argument("--subjects", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--set", dest="assign", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--sensitivity", action="store_true", help="also transit_speed -10 %% and +10 %%")
    parser.add_argument("--json", dest="json_path")
    args = parser.parse_args()
    scenario = load_scenario(args.scenario, parse_assignments(args.assign))
    cases = {"nominal": scenario}
    if args.sensitivity:
        v = scenario.protocol.robot.transit_speed
        cases |= {f"transit_speed {f:+.0%}": scenario.with_overrides({"transit_speed": str(v * (1 + f))})
                  for f in (-0.1, 0.1)}
    out = {}
    for label, sc in cases.items():
        summary = timing_summary(robot_only_runs(sc, args.subjects, args.seed))
        robot = sc.protocol.robot
        summary["ee_speed"], summary["transit_speed"] = robot.ee_speed, robot.transit_speed
        out[label] = summary
        print(f"[{label}] {args.scenario}: ee_speed {sc.protocol.robot.ee_speed} m/s, transit_speed "
              f"{sc.protocol.robot.transit_speed:.4g} m/s")
        print(format_summary(summary), flush=True)
    if args.json_path:
        write_json(args.json_path, out)


if __name__ == "__main__":
    main()
