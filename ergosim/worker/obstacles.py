"""The cell's furniture as obstacles of the worker's IK model, and the body's clearance from them.

The IK runs on the subject's standalone human (:mod:`ergosim.worker.ik`). For a cell, that model also holds
the furniture's solid boxes as static geoms, placed in the worker's frame, so that mink's collision
avoidance keeps the worker's segments out of them and :func:`clearance` can measure how close each posture
comes. The hands are not segments here: they take and set down parts on the furniture. Pairs are told apart
by contype/conaffinity in that model only (the scene's human never collides): the body's capsules have
contype 1, conaffinity 0; the obstacles contype 0, conaffinity 1.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import mink
import mujoco
import numpy as np
from mink.limits.collision_avoidance_limit import compute_contact_normal_jacobian

__all__ = ["IKModel", "ik_model", "clearance", "ClearanceLimit", "ClearanceTask", "CLEARANCE_RANGE",
           "FOREARM_CONTACT"]

CLEARANCE_RANGE = 0.1
"""m: distances are measured up to this; farther counts as this far."""
FOREARM_CONTACT = 0.02
"""m a forearm's capsule may sink into furniture the hand works on (assumed: the forearm's soft tissue and
the capsule's radius, 0.020 H, which is the forearm's girth at the elbow, thicker than at the wrist)."""


@dataclass(frozen=True)
class IKModel:
    """A compiled human with obstacles: the model, the body's segment geom ids (``forearms`` among them may
    touch, :data:`FOREARM_CONTACT`) and the obstacle geom ids."""

    model: mujoco.MjModel
    segments: tuple[int, ...]
    obstacles: tuple[int, ...]
    forearms: tuple[int, ...] = ()


def ik_model(spec: mujoco.MjSpec, boxes: Iterable[tuple[np.ndarray, np.ndarray, float]] = ()) -> IKModel:
    """Compile the human ``spec`` with ``boxes`` (centre (3,) [m], half sizes (3,) [m], yaw [deg], in the
    worker's frame) as obstacle geoms named ``obstacle_<k>``."""
    for g in spec.geoms:
        g.contype, g.conaffinity = 1, 0
    for k, (centre, half, yaw) in enumerate(boxes):
        a = np.deg2rad(yaw) / 2.0
        spec.worldbody.add_geom(name=f"obstacle_{k}", type=mujoco.mjtGeom.mjGEOM_BOX,
                                size=np.asarray(half, dtype=float).tolist(),
                                pos=np.asarray(centre, dtype=float).tolist(),
                                quat=[float(np.cos(a)), 0.0, 0.0, float(np.sin(a))], contype=0, conaffinity=1,
                                group=3)
    model = spec.compile()
    names = [model.geom(i).name for i in range(model.ngeom)]
    obstacles = tuple(i for i, n in enumerate(names) if n.startswith("obstacle_"))
    segments = tuple(i for i, n in enumerate(names)
                     if n.startswith("human_") and "_hand" not in n and "_foot" not in n)
    forearms = tuple(i for i in segments if names[i].endswith("_forearm"))
    return IKModel(model, segments, obstacles, forearms)


def clearance(model: mujoco.MjModel, data: mujoco.MjData, segments: Iterable[int],
              obstacles: Iterable[int], forearms: Iterable[int] = ()) -> float:
    """The smallest distance [m] between a segment and an obstacle at ``data``'s kinematics, beyond the
    forearms' contact allowance (negative: passing through), capped at :data:`CLEARANCE_RANGE`."""
    best = CLEARANCE_RANGE
    fromto = np.zeros(6)
    obstacles = tuple(obstacles)
    soft = set(forearms)
    pos, rbound = data.geom_xpos, model.geom_rbound
    for g in segments:
        allow = FOREARM_CONTACT if g in soft else 0.0
        for o in obstacles:
            # bounding spheres farther apart than the range cannot come closer: skip the exact distance
            if np.linalg.norm(pos[g] - pos[o]) - rbound[g] - rbound[o] + allow >= best:
                continue
            best = min(best, allow + mujoco.mj_geomDistance(model, data, g, o, CLEARANCE_RANGE, fromto))
    return float(best)


class ClearanceLimit(mink.Limit):
    """mink limit: each segment keeps ``least`` [m] (minus the forearms' contact allowance) from each
    obstacle, linearised per step. Unlike mink's CollisionAvoidanceLimit (a velocity damper that stops a
    pair from closing in but leaves a pair that already overlaps where it is), a pair inside its distance
    must move apart by ``gain`` of its deficit: a posture started inside the furniture is pushed out."""

    def __init__(self, model: mujoco.MjModel, built: IKModel, least: float = 0.005, gain: float = 0.5,
                 detect: float = 0.25) -> None:
        self.model = model
        soft = set(built.forearms)
        self.pairs = [(g, o, least - (FOREARM_CONTACT if g in soft else 0.0))
                      for g in built.segments for o in built.obstacles]
        self.gain, self.detect = gain, detect
        self._fromto, self._normal = np.zeros(6), np.zeros(3)
        self._jac1, self._jac2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> mink.Constraint:
        data = configuration.data
        rows, bounds = [], []
        for g, o, least in self.pairs:
            dist = mujoco.mj_geomDistance(self.model, data, g, o, self.detect, self._fromto)
            if dist >= self.detect:
                continue
            row = compute_contact_normal_jacobian(self.model, data, g, o, self._fromto, self._normal,
                                                  self._jac1, self._jac2)
            # mink's sign: the normal runs from the segment to the obstacle when apart, and flips inside
            rows.append((-1.0 if dist >= 0 else 1.0) * row)
            bounds.append(self.gain * (dist - least) / dt)
        if not rows:
            return mink.Constraint()
        return mink.Constraint(G=np.array(rows), h=np.array(bounds))


class ClearanceTask(mink.Task):
    """mink task: each segment-obstacle pair closer than ``least`` (less the forearms' allowance) is an error
    of its shortfall, weighted ``1 / sigma`` [1/m]: a posture that passes through the furniture is pulled out,
    more stiffly than the hand is held to its target, so the hand gives way first. Always feasible, unlike a
    hard limit that a hand on its target and a forearm on the furniture may contradict."""

    def __init__(self, model: mujoco.MjModel, built: IKModel, least: float = 0.005,
                 sigma: float = 5e-4) -> None:
        super().__init__(cost=np.zeros(1), gain=1.0, lm_damping=0.0)
        # measured out to a positive distance: mj_geomDistance needs a positive range to see a penetration
        self.limit = ClearanceLimit(model, built, least=least, gain=1.0, detect=max(least, 0.0) + 0.01)
        self.weight = 1.0 / sigma
        self.model = model

    def _rows(self, configuration: mink.Configuration) -> tuple[np.ndarray, np.ndarray]:
        con = self.limit.compute_qp_inequalities(configuration, 1.0)
        if con.inactive:
            return np.zeros((1, self.model.nv)), np.zeros(1)
        # G dq <= h is -d(dist)/dq dq <= dist - least: the shortfall min(dist - least, 0) = min(h, 0); pairs
        # clear of their distance are no error and pull nowhere
        short = con.h < 0.0
        return -con.G * short[:, None], np.where(short, con.h, 0.0)

    def compute_error(self, configuration: mink.Configuration) -> np.ndarray:
        return self._rows(configuration)[1]

    def compute_jacobian(self, configuration: mink.Configuration) -> np.ndarray:
        return self._rows(configuration)[0]

    def compute_qp_residual(self, configuration: mink.Configuration) -> tuple[np.ndarray, np.ndarray, float]:
        jac, err = self._rows(configuration)
        return self.weight * jac, -self.weight * err, 0.0
