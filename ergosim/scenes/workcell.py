"""A compiled workcell: MuJoCo model + data, its config, the actions' geometry, and the part welds.

Poses are world-frame: position (3,) [m] and quaternion (4,) wxyz. A part is held by switching on the
declared weld holder -> part with the relative pose of that instant (so nothing jumps); released parts are
ordinary free bodies that rest and fall under gravity.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import mujoco
import numpy as np

from ergosim.errors import ConfigError
from ergosim.human.mocap import MocapHuman
from ergosim.quat import angle_deg, conj, from_mat
from ergosim.robot.handle import RobotHandle, robot_prefix
from ergosim.robot.robot_model import get_robot
from ergosim.scenes.action_kinds import ActionKind, action_kind
from ergosim.scenes.build import receive_name, seat_name, weld_name
from ergosim.scenes.cellspec import CellSpec
from ergosim.scenes.shapes import PART_COLLISION

__all__ = ["ActionGeometry", "SeatResult", "Workcell"]


@dataclass(frozen=True)
class ActionGeometry:
    """Where action ``action`` takes ``part``: the origin of ``part`` ends on site ``target``.

    ``kind``: a registered kind (:mod:`ergosim.scenes.action_kinds`: place, insert, fasten, remove,
    handover). ``handover``: the site where a robot hands the part to the worker, else None (the robot
    finishes the action itself). ``turn_time`` [s]: how long a fastener is held and turned once seated.
    """

    action: str
    part: str
    kind: str
    target: str
    handover: str | None = None
    turn_time: float = 0.0

    @property
    def spec(self) -> ActionKind:
        return action_kind(self.kind)

    @property
    def seats(self) -> bool:
        """The action ends with the part seated in a slot (insert, fasten)."""
        return self.spec.seats

    @property
    def moves_assembly(self) -> bool:
        """The part is taken with everything seated in it (remove, handover)."""
        return self.spec.assembly

    @property
    def received(self) -> bool:
        """The action ends with a receiver outside the cell holding the part (handover)."""
        return self.spec.received

    @property
    def target_site(self) -> str:
        return self.target


class SeatResult(NamedTuple):
    """Outcome of :meth:`Workcell.seat`: errors to the seated pose [m], [deg]."""

    seated: bool
    pos_error: float
    rot_error_deg: float


_ROBOT_BIT = 2  # the robot's collision geoms have contype 2 (PART_COLLISION accepts it)


class Workcell:
    """One scene instance built from ``spec`` (:class:`~ergosim.scenes.cellspec.CellSpec`, also
    :attr:`config`). ``hand_bodies``: holder name -> body that holds (a robot's hand, the human's hands).

    ``human``: the articulated human model returned by :func:`~ergosim.scenes.build.attach_human`; the scene's
    mocap human is then driven through :attr:`human` (a :class:`~ergosim.human.mocap.MocapHuman`).
    """

    def __init__(self, spec: CellSpec, model: mujoco.MjModel, actions: dict[str, ActionGeometry],
                 hand_bodies: dict[str, str], human: mujoco.MjModel | None = None,
                 parks: dict | None = None) -> None:
        self.name = spec.name
        self.model = model
        self.data = mujoco.MjData(model)
        self.config = spec
        self.actions = dict(actions)
        self.hand_bodies = dict(hand_bodies)
        self.human = MocapHuman(model, human) if human is not None else None
        self.parks = dict(parks or {})
        """robot name -> :class:`~ergosim.scenes.park.ParkChoice`: where it parks, its clearance [m] from the
        worker's head, neck and chest, and whether that met the cell's rule."""
        self.home_key = model.keyframe("home").id
        self.parts = tuple(p.name for p in spec.parts)
        self.robots = tuple(r.name for r in spec.robots)
        self.robot_handles = {
            r.name: RobotHandle.find(model, r.name, robot_prefix(i, r.name), get_robot(r.model))
            for i, r in enumerate(spec.robots)}
        self._grip = {p.name: p.grip_width for p in spec.parts}
        self._body = {p: model.body(p).id for p in self.parts}
        self._hand = {h: model.body(b).id for h, b in hand_bodies.items()}
        self._weld = {(h, p): model.equality(weld_name(h, p)).id for h in hand_bodies for p in self.parts}
        seated = [(spec.slots()[a.target], a.part) for a in spec.actions if action_kind(a.kind).seats]
        self._host = {p: slot.host for slot, p in seated}
        self._upright = {p: tuple(slot.axis) == (0.0, 0.0, 1.0) for slot, p in seated}
        self._seat = {p: model.equality(seat_name(p)).id for _, p in seated}
        self._seat_site = {p: model.site(g.target).id for g in self.actions.values() if g.seats
                        for p in (g.part,)}
        self._receive = {g.part: model.equality(receive_name(g.part)).id for g in self.actions.values()
                         if g.received}
        self._collision_geoms = {p: np.flatnonzero((model.geom_bodyid == self._body[p])
                                                   & (model.geom_contype != 0)) for p in self.parts}
        self._all_collision_geoms = np.concatenate(list(self._collision_geoms.values()))
        self.reset()

    # -- poses ----------------------------------------------------------------------------------------------
    def site_pose(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        i = self.model.site(name).id
        return self.data.site_xpos[i].copy(), from_mat(self.data.site_xmat[i])

    def body_pose(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        i = self.model.body(name).id
        return self.data.xpos[i].copy(), self.data.xquat[i].copy()

    def robot_base_pose(self, robot: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Pose of the base body of ``robot`` (default: the cell's first robot)."""
        return self.body_pose(self.robot(robot).base)

    def robot_home(self, name: str | None = None) -> np.ndarray:
        """(n,) the arm configuration [rad] robot ``name`` (default: the first) parks in: its joints in the
        ``home`` keyframe, the pose chosen for the worker (:mod:`ergosim.scenes.park`)."""
        return self.model.key_qpos[self.home_key][self.robot(name).arm_qpos].copy()

    def robot(self, name: str | None = None) -> RobotHandle:
        """The :class:`~ergosim.robot.handle.RobotHandle` of robot ``name`` (default: the first)."""
        if not self.robot_handles:
            raise ConfigError("the workcell has no robot", where=self.name)
        if name is None:
            return next(iter(self.robot_handles.values()))
        try:
            return self.robot_handles[name]
        except KeyError:
            raise ConfigError(f"unknown robot {name!r}; robots: {', '.join(self.robots)}",
                              where=self.name) from None

    # -- reset ----------------------------------------------------------------------------------------------
    def reset(self) -> None:
        """Everything to the ``home`` keyframe; all welds off."""
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.home_key)
        self.data.eq_active[:] = 0
        self.pass_through(self._all_collision_geoms, False)
        mujoco.mj_forward(self.model, self.data)

    def reset_parts(self) -> None:
        """Lay the parts out again at their initial poses (welds off, at rest); robot and human untouched."""
        key_qpos = self.model.key_qpos[self.home_key]
        for eq in (*self._weld.values(), *self._seat.values(), *self._receive.values()):
            self.data.eq_active[eq] = 0
        self.pass_through(self._all_collision_geoms, False)
        for part in self.parts:
            jnt = self.model.body_jntadr[self._body[part]]
            qa, va = self.model.jnt_qposadr[jnt], self.model.jnt_dofadr[jnt]
            self.data.qpos[qa:qa + 7] = key_qpos[qa:qa + 7]
            self.data.qvel[va:va + 6] = 0.0
            self._wake(self._body[part])
        mujoco.mj_forward(self.model, self.data)

    # -- holding --------------------------------------------------------------------------------------------
    def _check(self, holder: str, part: str) -> None:
        if holder not in self._hand:
            raise ConfigError(f"unknown holder {holder!r}; holders: {', '.join(self._hand)}", where=self.name)
        if part not in self._body:
            raise ConfigError(f"unknown part {part!r}; parts: {', '.join(self.parts)}", where=self.name)

    def _wake(self, *bodies: int) -> None:
        """Wake the free parts among ``bodies``. MuJoCo's sleeping (enabled in the scenes) is velocity-based,
        and switching a weld off does not wake a part asleep in a hand; a changed ``qpos`` does, so the
        part's height is moved by one ulp."""
        for b in bodies:
            jnt = self.model.body_jntadr[b]
            if jnt >= 0 and self.model.jnt_type[jnt] == mujoco.mjtJoint.mjJNT_FREE:
                adr = self.model.jnt_qposadr[jnt] + 2
                self.data.qpos[adr] = np.nextafter(self.data.qpos[adr], np.inf)

    def _activate(self, eq: int, b1: int, b2: int) -> None:
        """Weld b2 to b1 at their current relative pose (eq_data: anchor 3, relpose pos 3 + quat 4, scale)."""
        p1, q1 = self.data.xpos[b1], self.data.xquat[b1]
        p2, q2 = self.data.xpos[b2], self.data.xquat[b2]
        r1 = self.data.xmat[b1].reshape(3, 3)
        rel_q = np.empty(4)
        mujoco.mju_mulQuat(rel_q, conj(q1), q2)
        self.model.eq_data[eq, 0:3] = 0.0
        self.model.eq_data[eq, 3:6] = r1.T @ (p2 - p1)
        self.model.eq_data[eq, 6:10] = rel_q
        self.data.eq_active[eq] = 1
        self._wake(b1, b2)

    def grasp(self, holder: str, part: str) -> None:
        """``holder`` (a robot's name, "human_right", "human_left") takes ``part`` where both are now.

        The weld *is* the grasp. For the robot, the part (with whatever is seated with it) stops colliding
        with the robot's geoms while held: fingers squeezing a welded part only add contact rows that fight
        the weld (and most of the solver's work while the robot carries). It still collides with the
        furniture, and the other parts still collide with the fingers."""
        self._check(holder, part)
        self._activate(self._weld[holder, part], self._hand[holder], self._body[part])
        if holder in self.robots:
            self._robot_contacts(part, False)

    def release(self, holder: str, part: str) -> None:
        self._check(holder, part)
        self.data.eq_active[self._weld[holder, part]] = 0
        if holder in self.robots:
            self._robot_contacts(part, True)
        self._wake(self._hand[holder], self._body[part])

    def assembly(self, part: str) -> list[str]:
        """The parts welded to ``part`` by seats, root first (a host and its seated parts move as one)."""
        root = part
        while root in self._host and self.is_seated(root):
            root = self._host[root]
        out = [root]
        grew = True
        while grew:
            grew = False
            for p, host in self._host.items():
                if p not in out and host in out and self.is_seated(p):
                    out.append(p)
                    grew = True
        return out

    def host_robot_contacts(self, part: str, on: bool) -> None:
        """Switch the robot bit of the collision affinity of the assembly that ``part`` is inserted into
        (its slot's host and what is seated with it), e.g. off while a robot pushes ``part`` into its seat."""
        self._robot_contacts(self._host[part], on, skip=part)

    def _robot_contacts(self, part: str, on: bool, skip: str | None = None) -> None:
        """Switch the robot bit of the collision affinity of ``part``'s assembly. Geoms switched off
        altogether (a part carried by the worker passes through everything) are left as they are."""
        m = self.model
        geoms = np.concatenate([self._collision_geoms[p] for p in self.assembly(part) if p != skip])
        live = geoms[m.geom_contype[geoms] != 0]
        if on:
            m.geom_conaffinity[live] |= _ROBOT_BIT
        else:
            m.geom_conaffinity[live] &= ~_ROBOT_BIT

    def collision_geoms(self, part: str) -> np.ndarray:
        """The collision geoms of ``part``'s assembly (:meth:`assembly`)."""
        return np.concatenate([self._collision_geoms[p] for p in self.assembly(part)])

    def pass_through(self, geoms: np.ndarray, on: bool) -> None:
        """Switch part collision geoms ``geoms`` off altogether (``on``: a part the kinematic worker carries
        passes through furniture and robot, like the worker) or back to the parts' own bits
        (``PART_COLLISION``)."""
        self.model.geom_contype[geoms] = 0 if on else PART_COLLISION["contype"]
        self.model.geom_conaffinity[geoms] = 0 if on else PART_COLLISION["conaffinity"]

    def holder_of(self, part: str) -> str | None:
        for (h, p), eq in self._weld.items():
            if p == part and self.data.eq_active[eq]:
                return h
        return None

    def is_held(self, holder: str, part: str) -> bool:
        self._check(holder, part)
        return bool(self.data.eq_active[self._weld[holder, part]])

    # -- assembly -------------------------------------------------------------------------------------------
    def seat_error(self, part: str) -> tuple[float, float]:
        """Distance [m] and angle [deg] between ``part`` and its seated pose in its slot."""
        pos, q = self.body_pose(part)
        i = self._seat_site[part]
        spos = self.data.site_xpos[i].copy()
        squat = from_mat(self.data.site_xmat[i])
        dq = np.empty(4)
        mujoco.mju_mulQuat(dq, conj(squat), q)
        return float(np.linalg.norm(pos - spos)), angle_deg(dq)

    def seat(self, part: str) -> SeatResult:
        """Weld ``part`` to its slot's host at its exact seated pose if within the seat tolerances."""
        if part not in self._seat:
            raise ConfigError(f"only parts with a slot are seated, got {part!r}; they are: "
                              f"{', '.join(self._seat)}", where=self.name)
        dist, angle = self.seat_error(part)
        ok = dist <= self.config.seat_tolerance and angle <= self.config.seat_tolerance_deg
        if ok:
            eq = self._seat[part]
            site = self._seat_site[part]
            self.model.eq_data[eq, 0:3] = 0.0
            self.model.eq_data[eq, 3:6] = self.model.site_pos[site]
            self.model.eq_data[eq, 6:10] = self.model.site_quat[site]
            self.data.eq_active[eq] = 1
            self._wake(self._body[self._host[part]], self._body[part])
        return SeatResult(ok, dist, angle)

    def is_seated(self, part: str) -> bool:
        return bool(self.data.eq_active[self._seat[part]])

    def unseat(self, part: str) -> None:
        self.data.eq_active[self._seat[part]] = 0
        self._wake(self._body[self._host[part]], self._body[part])

    # -- receivers and completion ---------------------------------------------------------------------------
    def receive(self, part: str, pos) -> SeatResult:
        """A receiver outside the cell (a second operator, a conveyor) takes ``part`` -- and what is seated in
        it -- where it now is, if its origin lies within ``place_tolerance`` of ``pos`` (3,) [m] (the handover
        kind's target): a weld to the world at the pose of that instant."""
        if part not in self._receive:
            raise ConfigError(f"only parts of handover actions are received, got {part!r}; they are: "
                              f"{', '.join(self._receive) or 'none'}", where=self.name)
        dist = float(np.linalg.norm(self.data.xpos[self._body[part]] - np.asarray(pos, dtype=float)))
        ok = dist <= self.config.place_tolerance
        if ok:
            self._activate(self._receive[part], 0, self._body[part])
        return SeatResult(ok, dist, 0.0)

    def is_received(self, part: str) -> bool:
        return part in self._receive and bool(self.data.eq_active[self._receive[part]])

    def action_done(self, geom: ActionGeometry) -> bool:
        """The completion check of ``geom``'s kind (:mod:`ergosim.scenes.action_kinds`), the same whoever did
        the action: seated (insert, fasten); taken by the receiver (handover); else released with its origin
        within ``place_tolerance`` of the target (place, remove)."""
        if geom.seats:
            return self.is_seated(geom.part)
        if geom.received:
            return self.is_received(geom.part)
        if self.holder_of(geom.part) is not None:
            return False
        pos, _ = self.body_pose(geom.part)
        target, _ = self.site_pose(geom.target)
        return float(np.linalg.norm(pos - target)) <= self.config.place_tolerance

    def grasp_site(self, part: str) -> str:
        """Site the robot's TCP goes to for a top-down grasp of ``part``: its own grasp site, or, once a part
        stands seated in an upward slot of it (covering its top), that part near its top end (the whole
        assembly is taken by what sticks up out of it)."""
        for p, host in self._host.items():
            if host == part and self._upright[p] and self.is_seated(p):
                end = f"{p}_grasp_end"
                if mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, end) >= 0:
                    return end
        return f"{part}_grasp"

    def grip_width(self, body: str) -> float:
        """Width [m] across the fingers of a top-down grasp of part ``body``."""
        return self._grip[body]

    def is_seat_part(self, part: str) -> bool:
        """``part`` has a slot it is inserted into."""
        return part in self._seat

    def grasp_body(self, part: str) -> str:
        """The body that carries :meth:`grasp_site` (the one to weld to the hand)."""
        return self.model.body(self.model.site_bodyid[self.model.site(self.grasp_site(part)).id]).name

    @property
    def holders(self) -> tuple[str, ...]:
        return tuple(self._hand)
