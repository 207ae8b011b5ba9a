"""Regenerate models/<name>/<name>.xml and models/<name>/assets/ from example-robot-data (installed package).

    python scripts/build_robot_mjcf.py [NAME ...]      # default: every registered robot
"""

from __future__ import annotations

import argparse

from ergosim.robot import robot_names
from ergosim.robot.model import write_model


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"robot models (default: all of {', '.join(robot_names())})")
    args = parser.parse_args()
    for name in args.names or robot_names():
        print(f"wrote {write_model(name)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
