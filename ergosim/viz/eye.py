"""Where the 3-D view's camera starts: the whole workcell and the worker in frame, from the cell's view.

The direction comes from the workcell's camera view (azimuth and elevation, as MuJoCo's free camera and
the video use them); the target and the distance come from the visible geometry itself (every geom the
viewer draws, except the floor plane, in the model's initial state), so a bigger cell is framed further out.
"""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np

from ergosim.viz.geometry import VISIBLE_GROUPS

__all__ = ["Eye", "frame_scene"]

_FOV_DEG = 65.0
"""The vertical field of view the framing assumes [deg]: measured from screenshots of rerun 0.41's web viewer
(a cell framed for 45 deg filled about half the view's height)."""


@dataclasses.dataclass(frozen=True)
class Eye:
    """A camera: ``position`` and ``look_target`` (3,) in the world frame [m], z up."""

    position: tuple[float, float, float]
    look_target: tuple[float, float, float]


def _visible_bounds(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """World-frame axis-aligned bounds (lo, hi) [m] of every visible geom but planes, initial state."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    keep = ((model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE) & np.isin(model.geom_group, VISIBLE_GROUPS)
            & (model.geom_rgba[:, 3] > 0))
    if not keep.any():
        return np.zeros(3), np.ones(3)
    rot = data.geom_xmat[keep].reshape(-1, 3, 3)
    local = model.geom_aabb[keep]  # (centre (3), half sizes (3)) in the geom frame
    centre = data.geom_xpos[keep] + np.einsum("gij,gj->gi", rot, local[:, :3])
    half = np.einsum("gij,gj->gi", np.abs(rot), local[:, 3:])
    return (centre - half).min(axis=0), (centre + half).max(axis=0)


def frame_scene(model: mujoco.MjModel, azimuth: float = 215.0, elevation: float = -28.0,
                margin: float = 1.15, aspect: float = 1.3) -> Eye:
    """The eye that sees every visible geom of ``model`` from ``azimuth``, ``elevation`` [deg] (MuJoCo's
    free-camera convention: the camera looks along (cos e cos a, cos e sin a, sin e)): every corner of the
    geoms' bounds inside a view of ``aspect`` (width / height), then ``margin`` × that distance."""
    lo, hi = _visible_bounds(model)
    centre = (lo + hi) / 2
    a, e = math.radians(azimuth), math.radians(elevation)
    forward = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    rel = corners - centre
    tan_v = math.tan(math.radians(_FOV_DEG) / 2)
    tan_h = tan_v * aspect
    # a corner at depth d - c·f from the eye fits when its offsets are within the half-angles
    need = np.maximum(rel @ forward + np.abs(rel @ up) / tan_v, rel @ forward + np.abs(rel @ right) / tan_h)
    distance = margin * float(need.max())
    eye = centre - distance * forward
    return Eye(tuple(float(x) for x in eye), tuple(float(x) for x in centre))
