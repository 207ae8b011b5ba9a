"""Offscreen pictures of a workcell (MuJoCo's renderer; set MUJOCO_GL=egl on a headless machine)."""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.scenes.workcell import Workcell

__all__ = ["VIEWS", "render_workcell"]

VIEWS = {"kwear-validation": (150.0, -25.0), "multi-subject": (300.0, -30.0)}
"""Default (azimuth, elevation) [deg] per scene: the worker, the robot and the parts all in view."""


def render_workcell(wc: Workcell, width: int = 960, height: int = 720, azimuth: float | None = None,
                    elevation: float | None = None, distance: float = 2.6,
                    lookat: tuple[float, float, float] = (0.35, 0.0, 1.0)) -> np.ndarray:
    """(height, width, 3) uint8 RGB image of the current state of ``wc`` from a free camera."""
    az, el = VIEWS.get(wc.name, (215.0, -28.0))
    cam = mujoco.MjvCamera()
    cam.azimuth = az if azimuth is None else azimuth
    cam.elevation = el if elevation is None else elevation
    cam.distance = distance
    cam.lookat[:] = lookat
    opt = mujoco.MjvOption()
    with mujoco.Renderer(wc.model, height=height, width=width) as renderer:
        renderer.update_scene(wc.data, camera=cam, scene_option=opt)
        return renderer.render().copy()
