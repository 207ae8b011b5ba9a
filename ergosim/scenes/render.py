"""Offscreen pictures of a workcell (MuJoCo's renderer; set MUJOCO_GL=egl on a headless machine)."""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.scenes.workcell import Workcell

__all__ = ["render_workcell"]


def render_workcell(wc: Workcell, width: int = 960, height: int = 720, azimuth: float = 215.0,
                    elevation: float = -28.0, distance: float = 2.6,
                    lookat: tuple[float, float, float] = (0.35, 0.0, 1.0)) -> np.ndarray:
    """(height, width, 3) uint8 RGB image of the current state of ``wc`` from a free camera."""
    cam = mujoco.MjvCamera()
    cam.azimuth, cam.elevation, cam.distance = azimuth, elevation, distance
    cam.lookat[:] = lookat
    opt = mujoco.MjvOption()
    with mujoco.Renderer(wc.model, height=height, width=width) as renderer:
        renderer.update_scene(wc.data, camera=cam, scene_option=opt)
        return renderer.render().copy()
