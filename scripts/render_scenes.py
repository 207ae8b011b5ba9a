"""Render every registered workcell to docs/img/scene_<name>.png (MUJOCO_GL=egl when headless).

    MUJOCO_GL=egl python scripts/render_scenes.py [--out docs/img]
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import matplotlib.image

from ergosim.atomic import write_bytes
from ergosim.scenes.registry import build_scene, scene_names
from ergosim.scenes.render import render_workcell


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "docs" / "img")
    parser.add_argument("--azimuth", type=float, default=None, help="camera azimuth [deg]")
    parser.add_argument("--elevation", type=float, default=None, help="camera elevation [deg]")
    args = parser.parse_args()
    for name in scene_names():
        wc = build_scene(name)
        image = render_workcell(wc, azimuth=args.azimuth, elevation=args.elevation)
        buf = io.BytesIO()
        matplotlib.image.imsave(buf, image, format="png")
        path = args.out / f"scene_{name.replace('-', '_')}.png"
        write_bytes(path, buf.getvalue())
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
