"""Where the 3-D view's camera starts: the whole workcell and the worker in frame, from the cell's view.

The direction comes from the workcell's camera view (azimuth and elevation, as MuJoCo's free camera and
the video use them); the target and the distance come from the visible geometry itself (the corners of
every geom the viewer draws, except the floor plane, in the model's initial state): the closest eye that
holds them all, the view centred on them, so a bigger cell is framed further out and none opens far out.
"""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np

from ergosim.viz.geometry import VISIBLE_GROUPS

__all__ = ["Eye", "frame_scene"]

_FOV_DEG = 55.0
"""The vertical field of view of rerun 0.41's 3-D view [deg], measured in its web viewer with the blueprint's
layout: markers 10, 20 and 25 deg off the look target land 90, 187 and 240 px from it (a focal length of
513 px) in a view 543 px high (1600x1000 window): 2 atan(271.5 / 513) = 55.8 deg. The view is 1.47 times as
wide as high."""


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


def _visible_corners(model: mujoco.MjModel) -> np.ndarray:
    """(8 g, 3) world corners of the boxes bounding every visible geom but planes, initial state."""
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    keep = ((model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE) & np.isin(model.geom_group, VISIBLE_GROUPS)
            & (model.geom_rgba[:, 3] > 0))
    if not keep.any():
        return np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    rot = data.geom_xmat[keep].reshape(-1, 3, 3)
    local = model.geom_aabb[keep]  # (centre (3), half sizes (3)) in the geom frame
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    corners = local[:, None, :3] + signs[None] * local[:, None, 3:]  # (g, 8, 3) geom frame
    world = data.geom_xpos[keep][:, None] + np.einsum("gij,gkj->gki", rot, corners)
    return world.reshape(-1, 3)


def frame_scene(model: mujoco.MjModel, azimuth: float = 215.0, elevation: float = -28.0,
                margin: float = 1.08, aspect: float = 1.47) -> Eye:
    """The eye that sees every visible geom of ``model`` from ``azimuth``, ``elevation`` [deg] (MuJoCo's
    free-camera convention: the camera looks along (cos e cos a, cos e sin a, sin e)): every corner of the
    geoms' boxes inside a view of ``aspect`` (width / height, the workcell panel of the blueprint), centred
    on them, then ``margin`` × that distance."""
    points = _visible_corners(model)
    a, e = math.radians(azimuth), math.radians(elevation)
    forward = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    tan_v = math.tan(math.radians(_FOV_DEG) / 2)
    tan_h = tan_v * aspect
    def fit(centre: np.ndarray) -> tuple[float, np.ndarray]:
        """The distance that holds every point (a point at depth d + r·f from the eye fits when its offsets
        are within the half-angles), and the move of the target that centres them in the view."""
        rel = points - centre
        need = np.maximum(np.abs(rel @ up) / tan_v, np.abs(rel @ right) / tan_h) - rel @ forward
        distance = margin * float(need.max())
        depth = distance + rel @ forward
        x, y = (rel @ right) / (depth * tan_h), (rel @ up) / (depth * tan_v)  # in the view, -1..1
        shift = distance * ((x.max() + x.min()) / 2 * tan_h * right + (y.max() + y.min()) / 2 * tan_v * up)
        return distance, shift

    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    for _ in range(4):
        distance, shift = fit(centre)
        if np.linalg.norm(shift) < 1e-4:
            break
        centre = centre + shift
    distance, _ = fit(centre)
    eye = centre - distance * forward
    return Eye(tuple(float(x) for x in eye), tuple(float(x) for x in centre))
