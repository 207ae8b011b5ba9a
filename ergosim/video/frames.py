"""Offscreen MuJoCo pictures of a workcell posed from recorded body poses, never from the live simulation.

:class:`PoseRenderer` owns a copy of the model and its own ``MjData``. For each frame it writes the world
poses of the bodies (as the loop recorded them) into that ``MjData`` and derives what MuJoCo's scene builder
reads from them: the body frames, the geoms' and sites' world poses (body pose composed with the geom's
local pose) and the lights'. Nothing is integrated and the simulation's ``MjData`` is never touched, so a
video cannot change a result.

Headless machines need an offscreen OpenGL: set ``MUJOCO_GL=egl`` (or ``osmesa``) before MuJoCo is imported
(the ``ergosim`` command does this itself when there is no display).
"""

from __future__ import annotations

import copy
import dataclasses

import mujoco
import numpy as np

from ergosim.errors import RenderError
from ergosim.quat import to_mat
from ergosim.scenes.cellspec import View

__all__ = ["PoseRenderer", "RenderQuality", "open_renderer", "gl_used"]

_GL_CONTEXTS = [0]  # offscreen contexts this process opened


def gl_used() -> bool:
    """True once this process opened an offscreen OpenGL context (a child forked from it would inherit
    the driver's state, so :mod:`ergosim.video.render_pool` spawns instead)."""
    return _GL_CONTEXTS[0] > 0


@dataclasses.dataclass(frozen=True)
class RenderQuality:
    """Offscreen settings, traded against time per frame on a software rasteriser (Mesa llvmpipe, 2 cores,
    960×540, measured): a 4096 px shadow map with 4× multisampling takes about 150 ms per frame, 2048 px
    with none about 65 ms. ``reflection`` off: the floor's mirror image costs a third of the frame and
    shows nothing of the work. ``shadow_size`` 1024 px: the light's depth map costs a quarter of 2048 px's
    and the shadows look alike at 960×540, their edges a little coarser (issue 38, stills in
    docs/video.md)."""

    shadow_size: int = 1024
    multisamples: int = 0
    reflection: bool = False


def open_renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """MuJoCo's offscreen renderer, or a one-line :class:`RenderError` saying how to get an OpenGL context."""
    _GL_CONTEXTS[0] += 1
    try:
        return mujoco.Renderer(model, height=height, width=width)
    except Exception as err:  # glfw without a display, no EGL driver, ...: MuJoCo raises several kinds
        import os  # noqa: PLC0415

        gl = os.environ.get("MUJOCO_GL", "") or "glfw (the default)"
        raise RenderError(f"cannot open an offscreen OpenGL context with MUJOCO_GL={gl}: "
                          f"{' '.join(str(err).split())}; on a machine without a display set MUJOCO_GL=egl "
                          "or MUJOCO_GL=osmesa before starting", where="render") from None


class PoseRenderer:
    """Renders ``model`` from body poses: ``render(pos (nbody, 3), quat (nbody, 4) wxyz) -> (h, w, 3) uint8``.

    ``view``: the free camera (a workcell's :class:`~ergosim.scenes.cellspec.View`). Use as a context
    manager, or call :meth:`close`.
    """

    def __init__(self, model: mujoco.MjModel, view: View, *, width: int = 960, height: int = 540,
                 quality: RenderQuality = RenderQuality()) -> None:
        m = copy.copy(model)  # render settings on our copy; the simulated model keeps its own
        m.vis.global_.offwidth = max(int(m.vis.global_.offwidth), width)
        m.vis.global_.offheight = max(int(m.vis.global_.offheight), height)
        m.vis.quality.shadowsize = quality.shadow_size
        m.vis.quality.offsamples = quality.multisamples
        self.model = m
        self.data = mujoco.MjData(m)
        mujoco.mj_forward(m, self.data)  # static lights, tendons, camera frames of the initial state
        self.width, self.height = width, height
        self._reflection = quality.reflection
        self._renderer = open_renderer(m, width, height)
        self.camera = mujoco.MjvCamera()
        self.camera.azimuth, self.camera.elevation = view.azimuth, view.elevation
        self.camera.distance = view.distance
        self.camera.lookat[:] = view.lookat
        self._option = mujoco.MjvOption()
        self._geom_body = m.geom_bodyid.copy()
        self._geom_pos = m.geom_pos.copy()
        self._geom_rot = to_mat(m.geom_quat)
        self._site_body = m.site_bodyid.copy()
        self._site_pos = m.site_pos.copy()
        self._site_rot = to_mat(m.site_quat)
        moving = m.light_bodyid != 0  # lights on the world body never move
        self._light = np.flatnonzero(moving)
        self._light_body = m.light_bodyid[moving]

    def pose(self, pos: np.ndarray, quat: np.ndarray) -> None:
        """Write the world poses of every body into the renderer's own ``MjData``."""
        m, d = self.model, self.data
        pos = np.asarray(pos, dtype=float)
        if pos.shape != (m.nbody, 3) or np.shape(quat) != (m.nbody, 4):
            raise ValueError(f"expected body poses of shape ({m.nbody}, 3) and ({m.nbody}, 4), "
                             f"got {pos.shape} and {np.shape(quat)}")
        rot = to_mat(quat)
        d.xpos[:] = pos
        d.xquat[:] = quat
        d.xmat[:] = rot.reshape(-1, 9)
        rg = rot[self._geom_body]
        d.geom_xpos[:] = pos[self._geom_body] + np.einsum("gij,gj->gi", rg, self._geom_pos)
        d.geom_xmat[:] = (rg @ self._geom_rot).reshape(-1, 9)
        if m.nsite:
            rs = rot[self._site_body]
            d.site_xpos[:] = pos[self._site_body] + np.einsum("sij,sj->si", rs, self._site_pos)
            d.site_xmat[:] = (rs @ self._site_rot).reshape(-1, 9)
        for light, body in zip(self._light, self._light_body, strict=True):
            d.light_xpos[light] = pos[body] + rot[body] @ m.light_pos[light]
            d.light_xdir[light] = rot[body] @ m.light_dir[light]

    def render(self, pos: np.ndarray, quat: np.ndarray) -> np.ndarray:
        """(height, width, 3) uint8 RGB picture of the bodies at ``pos``, ``quat``."""
        self.pose(pos, quat)
        r = self._renderer
        r.update_scene(self.data, camera=self.camera, scene_option=self._option)
        r.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = int(self._reflection)
        return r.render()

    def close(self) -> None:
        self._renderer.close()

    def __enter__(self) -> PoseRenderer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
