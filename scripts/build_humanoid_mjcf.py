"""Write models/humanoid_upper/humanoid_upper.xml (nominal 1.75 m stature) from ergosim.human.

Usage: python scripts/build_humanoid_mjcf.py [--stature 1.75] [--out models/humanoid_upper/humanoid_upper.xml]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.atomic import write_text
from ergosim.human import humanoid_xml, segment_lengths

DEFAULT_OUT = Path(__file__).resolve().parents[1] / "models" / "humanoid_upper" / "humanoid_upper.xml"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--stature", type=float, default=1.75, help="stature [m]")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    args = parser.parse_args()
    write_text(args.out, humanoid_xml(segment_lengths(args.stature)))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
