"""Offscreen pictures of a workcell (MuJoCo's renderer; set MUJOCO_GL=egl on a headless machine)."""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.scenes.workcell import Workcell

__all__ = ["render_workcell"]


def render_workcell(wc: Workcell, width: int = 960, height: int = 720, azimuth: float | None = None,
                    elevation: float | None = None, distance: float | None = None,
                    lookat: tuple[float, float, float] | None = None, view: str | None = None) -> np.ndarray:
    """(height, width, 3) uint8 RGB image of the current state of ``wc`` from a free camera: the cell's
    ``view`` (its first view by default), with any of azimuth, elevation [deg], distance [m] and lookat (3,)
    [m] given here winning."""
    v = wc.config.view(view)
    cam = mujoco.MjvCamera()
    cam.azimuth = v.azimuth if azimuth is None else azimuth
    cam.elevation = v.elevation if elevation is None else elevation
    cam.distance = v.distance if distance is None else distance
    cam.lookat[:] = v.lookat if lookat is None else lookat
    opt = mujoco.MjvOption()
    with mujoco.Renderer(wc.model, height=height, width=width) as renderer:
        renderer.update_scene(wc.data, camera=cam, scene_option=opt)
        return renderer.render().copy()
