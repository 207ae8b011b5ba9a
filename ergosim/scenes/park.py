"""Where a robot parks in a workcell: a home pose chosen for the worker.

A robot's manufacturer ready pose (``RobotModel.home``) says nothing about the person next to it: in the
bundled cells it held the gripper 0.3-0.4 m from the worker's face and chest. The park pose is the ready
pose turned about the robot's first (vertical) joint and, if need be, folded towards its ``tuck`` posture,
the least change from the ready pose (joint-space distance [rad]) whose closest point keeps
:attr:`ParkRule.clearance` from the worker's head, neck and chest (ISO/TS 15066 Annex A body regions 1-3
and 5, where contact is to be avoided or tolerated least) at the worker's rest posture, without touching
furniture, parts or another robot. Where no candidate keeps the clearance (a base placed too close to the
worker), the robot keeps its ready pose -- a half-way pose turned towards other furniture may leave the
arm a path through it, which the transits do not check -- and :attr:`ParkChoice.met` is False, so the
pre-run check says how close it parks. Distances are MuJoCo's between collision geoms
(``mj_geomDistance``), world frame, metres.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import mujoco
import numpy as np

__all__ = ["ParkRule", "ParkChoice", "HEAD_AND_CHEST", "HEAD_AND_NECK", "HANDOVER_CLEARANCE", "choose_park",
           "robot_geoms", "clearance_to"]

HEAD_AND_CHEST = ("human_head", "human_neck", "human_chest")
"""The human model's geoms of ISO/TS 15066's skull and face, neck and chest regions."""

HEAD_AND_NECK = ("human_head", "human_neck")
"""The human model's geoms of ISO/TS 15066's body region 1 (skull and forehead, face, neck), the regions
with the lowest biomechanical limits, where contact is to be avoided: what a hand-over keeps its distance
from. The chest (region 2) is left out there: a part presented at the worker's own bench, where the worker
needs it, comes within reach of the torso by design, and contact there is what power and force limiting
bounds (ISO/TS 15066 Table A.2). Parking (:class:`ParkRule`) keeps away from the chest as well."""

HANDOVER_CLEARANCE = 0.2
"""[m] what the robot keeps from the worker's head and neck (:data:`HEAD_AND_NECK`) while it holds a part
out at a hand-over (the part itself may come closer: the worker's hand takes it). Assumed: about a hand's
length (0.108 of stature, Drillis & Contini; 0.19 m at 1.75 m), so a hand reaching for the part fits
between."""


@dataclasses.dataclass(frozen=True)
class ParkRule:
    """``clearance`` [m]: the distance the parked robot keeps from ``regions`` (geom names of the worker).

    0.5 m (assumed): the separation at which ISO 13855:2010 §6.2 stops counting an approach as a reach of
    the hand and arm (K = 2000 mm/s for S <= 500 mm) and counts it as a movement of the whole body
    (K = 1600 mm/s): parked at least that far from the head and chest, the robot is out of the way of the
    worker's head and upper body as long as the worker does not step towards it.
    ``yaw_step`` [deg], ``max_yaw`` [deg] and ``tuck_steps``: the candidate grid (turns of the first joint
    in both directions up to ``max_yaw`` and its limits -- 90 deg keeps the arm on the side it works on, so
    its way to the parts never swings round over them (assumed); folds 0, 1/n, ..., 1 of the way to the
    tuck posture)."""

    clearance: float = 0.5
    regions: tuple[str, ...] = HEAD_AND_CHEST
    yaw_step: float = 5.0
    max_yaw: float = 90.0
    tuck_steps: int = 4


class ParkChoice(NamedTuple):
    """``q`` (n,) the park configuration [rad]; ``clearance`` [m] its distance to the regions (inf without
    a worker); ``met``: ``clearance`` >= the rule's; ``yaw`` [rad] the turn of the first joint and
    ``tuck`` (0..1) the fold applied to the ready pose."""

    q: np.ndarray
    clearance: float
    met: bool
    yaw: float
    tuck: float


def robot_geoms(model: mujoco.MjModel, base: str) -> list[int]:
    """The collision geoms of the robot whose base body is ``base`` (its subtree; not its visuals)."""
    root = model.body(base).id
    below = {root}
    for b in range(root + 1, model.nbody):
        if model.body_parentid[b] in below:
            below.add(b)
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] in below
            and (model.geom_contype[g] or model.geom_conaffinity[g])]


def clearance_to(model: mujoco.MjModel, data: mujoco.MjData, geoms, regions, limit: float = 2.0) -> float:
    """Smallest distance [m] between ``geoms`` and ``regions`` (geom ids) at ``data``'s kinematics, capped
    at ``limit``."""
    fromto = np.zeros(6)
    return min((mujoco.mj_geomDistance(model, data, a, b, limit, fromto) for a in geoms for b in regions),
               default=np.inf)


def _candidates(home: np.ndarray, tuck: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                rule: ParkRule) -> list[tuple[float, float, float, np.ndarray]]:
    """(cost, yaw, fold, q) in order of cost: the joint-space distance [rad] from the ready pose."""
    out = []
    step = np.radians(rule.yaw_step)
    widest = min(max(upper[0] - home[0], home[0] - lower[0]), np.radians(rule.max_yaw))
    n = int(np.floor(widest / step + 1e-9))
    for k in range(rule.tuck_steps + 1):
        fold = k / rule.tuck_steps if rule.tuck_steps else 0.0
        base = home + fold * (tuck - home)
        for i in range(-n, n + 1):
            q = base.copy()
            q[0] = home[0] + i * step
            if np.all(q >= lower) and np.all(q <= upper):
                out.append((float(np.linalg.norm(q - home)), i * step, fold, q))
    out.sort(key=lambda c: (c[0], abs(c[1]), c[1]))
    return out


def _touches(model: mujoco.MjModel, data: mujoco.MjData, mine: set[int], depth: float) -> bool:
    """A contact between one of ``mine`` and any other geom deeper than ``depth`` [m]."""
    mujoco.mj_collision(model, data)
    for c in data.contact[:data.ncon]:
        if (c.geom1 in mine) != (c.geom2 in mine) and c.dist < -depth:
            return True
    return False


def choose_park(model: mujoco.MjModel, data: mujoco.MjData, arm_qpos: np.ndarray, base: str,
                home, tuck, lower, upper, rule: ParkRule = ParkRule(), depth: float = 0.003,
                others=()) -> ParkChoice:
    """The park pose of one robot (module docstring) in the scene ``model``/``data`` as it stands (the
    worker at rest, the parts laid out, other robots where ``data`` has them). ``arm_qpos`` (n,) the arm's
    qpos addresses, ``base`` its base body; ``home``, ``tuck`` (n,) [rad]; ``lower``/``upper`` joint
    limits; ``others``: geoms to keep clear of that do not collide with the robot (another robot's).
    ``data.qpos`` is left as it was. A clearance of 0 keeps the ready pose."""
    home, tuck = np.asarray(home, dtype=float), np.asarray(tuck, dtype=float)
    regions = [model.geom(n).id for n in rule.regions if _has_geom(model, n)]
    if not regions or rule.clearance <= 0:
        return ParkChoice(home, np.inf if not regions else 0.0, True, 0.0, 0.0)
    mine = robot_geoms(model, base)
    mine_set = set(mine)
    saved = data.qpos.copy()
    try:
        for _, yaw, fold, q in _candidates(home, tuck, np.asarray(lower), np.asarray(upper), rule):
            data.qpos[arm_qpos] = q
            mujoco.mj_kinematics(model, data)
            if _touches(model, data, mine_set, depth) or clearance_to(model, data, mine, others, 0.05) < 0:
                continue
            d = clearance_to(model, data, mine, regions, rule.clearance + 1.0)
            if d >= rule.clearance:
                return ParkChoice(q, d, True, yaw, fold)
        data.qpos[arm_qpos] = home
        mujoco.mj_kinematics(model, data)
        ready = clearance_to(model, data, mine, regions, rule.clearance + 1.0)
    finally:
        data.qpos[:] = saved
        mujoco.mj_kinematics(model, data)
    return ParkChoice(home, ready, False, 0.0, 0.0)


def _has_geom(model: mujoco.MjModel, name: str) -> bool:
    return mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name) >= 0
