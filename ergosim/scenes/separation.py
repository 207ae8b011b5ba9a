"""Human-robot separation in a workcell: the robot's links and the worker's segments as capsules.

The worker's segments are capsules already (:mod:`ergosim.human.mjcf`). A robot link is a mesh; it is
bounded by a capsule along its mesh's longest bounding-box axis, whose radius covers the box's cross-section
(so the capsule contains the link; the excess is part of the robot's position uncertainty, ISO/TS 15066
Z_r). A part a robot holds is bounded the same way and counts as the robot. The separation is the smallest
surface-to-surface distance between any robot capsule and any worker capsule, negative where they overlap.
World frame, metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["Capsules", "Separation", "SeparationModel", "segment_distances"]


@dataclass(frozen=True)
class Capsules:
    """Capsules of some geoms: ``geoms`` (n,) ids; per geom the local centre (n, 3), the local axis index
    (n,), the half segment length (n,) and the radius (n,) [m]."""

    geoms: np.ndarray
    centre: np.ndarray
    axis: np.ndarray
    half: np.ndarray
    radius: np.ndarray

    def segments(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """World end points (n, 3), (n, 3) of the capsules' segments."""
        rot = data.geom_xmat[self.geoms].reshape(-1, 3, 3)
        centre = data.geom_xpos[self.geoms] + np.einsum("nij,nj->ni", rot, self.centre)
        axis = rot[np.arange(len(self.geoms)), :, self.axis] * self.half[:, None]
        return centre - axis, centre + axis


def capsules_of(model: mujoco.MjModel, geoms) -> Capsules:
    """Bounding capsules of ``geoms``: a capsule or a sphere as it is, another geom from its bounding box."""
    geoms = np.asarray(list(geoms), dtype=np.int64)
    n = len(geoms)
    centre, axis, half, radius = np.zeros((n, 3)), np.full(n, 2), np.zeros(n), np.zeros(n)
    for i, g in enumerate(geoms.tolist()):
        kind, size = model.geom_type[g], model.geom_size[g]
        if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
            half[i], radius[i] = size[1], size[0]
        elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            radius[i] = size[0]
        else:
            box = model.geom_aabb[g]
            centre[i], extent = box[:3], box[3:]
            axis[i] = int(np.argmax(extent))
            half[i] = extent[axis[i]]
            radius[i] = float(np.linalg.norm(np.delete(extent, axis[i])))
    return Capsules(geoms, centre, axis, half, radius)


def segment_distances(p0, p1, q0, q1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest points between segments p0-p1 and q0-q1, (n, 3) arrays of pairs: the distances (n,) and the
    parameters s, t in [0, 1] of the closest points on each (Ericson, Real-Time Collision Detection,
    §5.1.9)."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = (d1 * d1).sum(axis=1)
    e = (d2 * d2).sum(axis=1)
    f = (d2 * r).sum(axis=1)
    c = (d1 * r).sum(axis=1)
    b = (d1 * d2).sum(axis=1)
    a_ok, e_ok = a > 1e-12, e > 1e-12
    a_safe, e_safe = np.where(a_ok, a, 1.0), np.where(e_ok, e, 1.0)
    denom = a * e - b * b
    s = np.where(a_ok & (denom > 1e-12), np.clip((b * f - c * e) / np.where(denom > 1e-12, denom, 1.0),
                                                  0.0, 1.0), 0.0)
    t = np.where(e_ok, (b * s + f) / e_safe, 0.0)
    s_lo, s_hi = np.clip(-c / a_safe, 0.0, 1.0), np.clip((b - c) / a_safe, 0.0, 1.0)
    s = np.where(t < 0.0, s_lo, np.where(t > 1.0, s_hi, s)) * a_ok
    s = np.where(e_ok, s, s_lo * a_ok)  # q is a point: the closest point of p to it
    t = np.clip(t, 0.0, 1.0)
    gap = (p0 + d1 * s[:, None]) - (q0 + d2 * t[:, None])
    return np.sqrt((gap * gap).sum(axis=1)), s, t


@dataclass(frozen=True)
class Separation:
    """The separation of one robot from the worker now: ``distance`` [m] surface to surface (negative:
    overlap), the closest points on the robot and on the worker (3,) [m], and the worker's capsule index."""

    distance: float
    robot_point: np.ndarray
    human_point: np.ndarray
    human_capsule: int
    human_t: float


class SeparationModel:
    """The capsules of a workcell's robots and worker, from its compiled model.

    ``robot_geoms``: robot name -> its collision geoms (the bodies under its base); ``human``:
    the worker's segment geoms."""

    def __init__(self, model: mujoco.MjModel, robot_bases: dict[str, str], human_bodies) -> None:
        self.model = model
        parent = model.body_parentid
        collide = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
        self.robots: dict[str, Capsules] = {}
        for name, base in robot_bases.items():
            root = model.body(base).id
            bodies = {b for b in range(model.nbody) if _under(parent, b, root)}
            geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] in bodies and collide[g]]
            self.robots[name] = capsules_of(model, geoms)
        ids = {model.body(b).id for b in human_bodies}
        self.human = capsules_of(model, [g for g in range(model.ngeom) if model.geom_bodyid[g] in ids
                                         and not _is_duplicate(model, g)])

    def human_segments(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        return self.human.segments(data)

    def separation(self, data: mujoco.MjData, robot: str, human: tuple[np.ndarray, np.ndarray],
                   extra: Capsules | None = None) -> Separation:
        """The separation of ``robot`` (and the capsules ``extra``, a part it holds) from the worker's
        capsule segments ``human`` (from :meth:`human_segments`)."""
        caps = [self.robots[robot]] + ([extra] if extra is not None and len(extra.geoms) else [])
        ends = [c.segments(data) for c in caps]
        p0 = np.concatenate([e[0] for e in ends]) if len(ends) > 1 else ends[0][0]
        p1 = np.concatenate([e[1] for e in ends]) if len(ends) > 1 else ends[0][1]
        radius = np.concatenate([c.radius for c in caps]) if len(caps) > 1 else caps[0].radius
        # only the pairs whose bounding spheres could hold the closest pair get the exact test
        q0, q1, hr = human[0], human[1], self.human.radius
        mid_r, mid_h = (p0 + p1) / 2, (q0 + q1) / 2
        reach_r = np.linalg.norm(p1 - p0, axis=1) / 2
        reach_h = np.linalg.norm(q1 - q0, axis=1) / 2
        centre = np.linalg.norm(mid_r[:, None, :] - mid_h[None, :, :], axis=2) - radius[:, None] - hr[None, :]
        lower = centre - reach_r[:, None] - reach_h[None, :]
        ri, hi = np.nonzero(lower <= centre.min())
        dist, s, t = segment_distances(p0[ri], p1[ri], q0[hi], q1[hi])
        gap = dist - radius[ri] - hr[hi]
        k = int(np.argmin(gap))
        i, j = int(ri[k]), int(hi[k])
        rp = p0[i] + (p1[i] - p0[i]) * s[k]
        hp = human[0][j] + (human[1][j] - human[0][j]) * t[k]
        return Separation(float(gap[k]), rp, hp, j, float(t[k]))


def _under(parent: np.ndarray, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = int(parent[body])
    return root == 0


def _is_duplicate(model: mujoco.MjModel, g: int) -> bool:
    """A second geom on the same body with the same shape and place (the hand's collision twin)."""
    for other in range(g):
        if (model.geom_bodyid[other] == model.geom_bodyid[g] and model.geom_type[other] == model.geom_type[g]
                and np.allclose(model.geom_size[other], model.geom_size[g])
                and np.allclose(model.geom_pos[other], model.geom_pos[g])):
            return True
    return False
