"""Render every registered workcell, and the bracket example, with each bundled robot to docs/img.

    MUJOCO_GL=egl python scripts/render_scenes.py [--out docs/img] [--robots panda,ur5]

Writes scene_<name>.png with the workcell's own robot and scene_<name>_<robot>.png with each other one.
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import matplotlib.image

from ergosim.atomic import write_bytes
from ergosim.robot import robot_names
from ergosim.scenes.registry import build_scene, scene_names
from ergosim.scenes.render import render_workcell

ROOT = Path(__file__).resolve().parents[1]
EXTRA = {"bracket": ROOT / "examples" / "own_workcell" / "bracket_cell.toml"}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    parser.add_argument("--robots", default=",".join(robot_names()),
                        help="robot models, the first the cells' own (default: every registered one)")
    parser.add_argument("--azimuth", type=float, default=None, help="camera azimuth [deg]")
    parser.add_argument("--elevation", type=float, default=None, help="camera elevation [deg]")
    args = parser.parse_args()
    cells = {name: name for name in scene_names()} | {k: str(v) for k, v in EXTRA.items()}
    for i, robot in enumerate(args.robots.split(",")):
        for name, source in cells.items():
            wc = build_scene(source, **({} if i == 0 else {"robots.robot.model": robot}))
            image = render_workcell(wc, azimuth=args.azimuth, elevation=args.elevation)
            buf = io.BytesIO()
            matplotlib.image.imsave(buf, image, format="png")
            path = args.out / f"scene_{name.replace('-', '_')}{'' if i == 0 else '_' + robot}.png"
            write_bytes(path, buf.getvalue())
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
