"""Regenerate models/panda/panda.xml from example-robot-data's URDF (installed package).

    python scripts/build_panda_mjcf.py [--out models/panda/panda.xml]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.atomic import write_text
from ergosim.robot.model import panda_mjcf_text


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = Path(__file__).resolve().parents[1] / "models" / "panda" / "panda.xml"
    parser.add_argument("--out", type=Path, default=default, help="output MJCF file")
    args = parser.parse_args()
    write_text(args.out, panda_mjcf_text())
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
