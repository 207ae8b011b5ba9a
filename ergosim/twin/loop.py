"""The digital-twin loop of paper Fig. 1 for one subject in one mode.

Every control tick (the mocap rate, 60 Hz by default) the worker's true posture sets the human's ``qpos``
(and so the scene's mocap segments, :class:`~ergosim.human.mocap.MocapHuman`), the robot's skill sets its
actuators, and MuJoCo steps the plant. Every ergonomics tick (20 Hz) the measured mocap frame's RULA part
scores G_i advance KWear (eq. 3-5) -- or, for a risk index on another posture feature (REBA's part
scores, :mod:`ergosim.ergonomics.features`), that feature's row. When an action completes -- detected in
the scene: a profile seated, a part placed, a handover taken -- the risk index predicts V̂ for every
candidate action (eq. 9), the cost model turns it into hyper-arc costs (eq. 10-11), and the planner
(RecursiveAO*, Algorithm 2) returns the next (action, agent), which is dispatched to the robot's skill or
to the worker's motion.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.ergonomics.risk_index import RiskIndex
from ergosim.errors import ModelError
from ergosim.posture import KWEAR_JOINTS, STANCE
from ergosim.twin.records import TICK_COLUMNS, TickLog
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.motion import WORKER_MEASURES

__all__ = ["Plant", "PlantHook", "PLANT_HOOKS"]

_M = len(KWEAR_JOINTS)
# When nothing is queued the worker holds the rest posture, measured in chunks of this many seconds (one
# vectorised RULA pass each); a chunk cut short by the next action costs only unused frames.
_REST_CHUNK = 5.0
# tick-log columns copied from the segment's per-frame table, and KWear's
_SCORES = slice(TICK_COLUMNS.index("acting"), TICK_COLUMNS.index("rula_grand") + 1)
_KWEAR = slice(TICK_COLUMNS.index(f"kwear_{KWEAR_JOINTS[0]}"),
               TICK_COLUMNS.index(f"kwear_{KWEAR_JOINTS[-1]}") + 1)
_STANCE = slice(TICK_COLUMNS.index(STANCE[0]), TICK_COLUMNS.index(WORKER_MEASURES[-1]) + 1)
_END = len(TICK_COLUMNS)  # the extra columns of a REBA index follow the paper's (and the stance)


PLANT_HOOKS = ("on_grasp", "on_release", "before_physics", "after_step")
"""What the plant calls on each of its hooks during a control tick, in this order (the way dm_control's
composer ``Task`` names ``before_step`` and ``after_step``)."""


class PlantHook:
    """Something that acts during the plant's control ticks; override any of :data:`PLANT_HOOKS`.

    - ``on_grasp(plant)``: the worker's hand closes on this tick (the segment's grasp frame);
    - ``on_release(plant)``: the worker's hand opens on this tick;
    - ``before_physics(plant, frame)``: the human is posed at the worker segment's ``frame``; physics next;
    - ``after_step(plant)``: physics stepped and, when due, the ergonomics tick logged.
    """

    def on_grasp(self, plant: Plant) -> None:
        pass

    def on_release(self, plant: Plant) -> None:
        pass

    def before_physics(self, plant: Plant, frame: int) -> None:
        pass

    def after_step(self, plant: Plant) -> None:
        pass


class Plant:
    """Time keeping, physics and per-tick ergonomics for one workcell and one worker.

    ``mocap_rate`` [Hz] is the control tick; physics takes ``n_sub`` MuJoCo steps per control tick with the
    timestep adjusted so the two clocks agree exactly; the ergonomics tick runs every ``tick_every`` control
    ticks. ``robot`` (a :class:`~ergosim.twin.robot_track.RobotTrack` or None) steps the physics itself while
    one of its skills is active. ``kwear``: the worker's online risk index (the paper's KWear on RULA part
    scores, or another feature's, e.g. KWear on REBA part scores), advanced every ergonomics tick with its
    feature's row; ticks.csv gains the track's extra feature columns and, for an index with more joints
    than the paper's five, ``kwear_<joint>`` for each further joint. ``hooks`` (:class:`PlantHook`) act at
    the named points of every tick (:data:`PLANT_HOOKS`): the worker's hand on a part, speed and separation
    monitoring.
    """

    def __init__(self, cell, track: WorkerTrack, kwear: RiskIndex, *, mocap_rate: float,
                 ergonomics_rate: float, physics_dt: float, record_bodies: bool = False) -> None:
        self.cell = cell
        self.model: mujoco.MjModel = cell.model
        self.data: mujoco.MjData = cell.data
        self.track = track
        if cell.human is None:
            raise ModelError("the workcell has no human", where=cell.name)
        self.human = cell.human
        self.kwear = kwear
        self.dt_control = 1.0 / mocap_rate
        self.n_sub = max(1, int(round(self.dt_control / physics_dt)))
        self.model.opt.timestep = self.dt_control / self.n_sub
        self.tick_every = int(round(mocap_rate / ergonomics_rate))
        self.dt_tick = self.tick_every * self.dt_control
        self.ticks = 0  # control ticks since the start
        self.repetition = 0
        extra_joints = tuple(j for j in kwear.joints if j not in KWEAR_JOINTS)
        scorer = track.scorer
        self._extra = scorer.columns if scorer is not None else ()
        self.log = TickLog(TICK_COLUMNS + self._extra + tuple(f"kwear_{j}" for j in extra_joints))
        self._feature = kwear.features
        self._m = len(kwear.joints)
        self.indices: list[RiskIndex] = []
        """Further risk indices fed every ergonomics tick with their own feature's row (a mode's stateful
        index other than ``kwear``, e.g. one on joint angles); not logged."""
        self.robot = None
        """The acting robot's track (or a group of tracks): it steps the physics while a skill is active."""
        self.hooks: list[PlantHook] = []
        self._zero_g = np.zeros(self._m)
        self._posed = None  # the segment whose pose the scene's human shows
        self._row = np.empty(len(self.log.columns))
        self.record_bodies = record_bodies
        self.body_pos: list[np.ndarray] = []
        self.body_quat: list[np.ndarray] = []
        self.tick_times: list[float] = []

    @property
    def v(self) -> np.ndarray:
        """(5,) current KWear per joint (KWEAR_JOINTS order): the index's first five joints."""
        return self.kwear.value[:_M]

    @property
    def dropouts(self) -> int:
        return self.kwear.dropouts

    @property
    def time(self) -> float:
        """Simulated time [s], exact multiple of the control period."""
        return self.ticks * self.dt_control

    # -- one control tick ----------------------------------------------------------------------------------
    def step(self) -> None:
        track = self.track
        seg = track.start_rest(_REST_CHUNK) if track.exhausted else track.segment
        k = track.advance()
        d = self.data
        if seg is not self._posed or not seg.static:
            self.human.pose(d, seg.qpos[k])
            self._posed = seg
        hooks = self.hooks
        if hooks:
            if k == seg.grasp_frame and track.index == k + 1:
                for h in hooks:
                    h.on_grasp(self)
            if k == seg.release_frame and track.index == k + 1:
                for h in hooks:
                    h.on_release(self)
            for h in hooks:
                h.before_physics(self, k)
        robot = self.robot
        if robot is not None and robot.active:
            robot.advance(self.model, d, self.n_sub)
        else:
            mujoco.mj_step(self.model, d, nstep=self.n_sub)
        self.ticks += 1
        if self.ticks % self.tick_every == 0:
            self._ergonomics_tick(seg, k)
        for h in hooks:
            h.after_step(self)

    def _ergonomics_tick(self, seg, k: int) -> None:
        """Paper eq. 3-5 over one ergonomics period: wear while acting, recovery while resting. A dropout
        (NaN frame) is counted by the index and V holds, so NaN never reaches KWear."""
        if seg.acting:
            self.kwear.update(seg.g_by[self._feature][k], self.dt_tick)
        else:
            self.kwear.update(self._zero_g, self.dt_tick, resting=True)
        for index in self.indices:
            if seg.acting:
                index.update(seg.g_by[index.features][k], self.dt_tick)
            else:
                index.update(np.zeros(len(index.joints)), self.dt_tick, resting=True)
        row = self._row
        row[0] = self.repetition
        row[1] = self.time
        row[_SCORES] = seg.scores[k]
        v = self.kwear.value
        row[_KWEAR] = v[:_M]
        row[_STANCE] = seg.motion.tick_stance[k]
        if len(row) > _END:
            n = len(self._extra)
            row[_END:_END + n] = seg.extra[k]
            row[_END + n:] = v[_M:]
        self.log.append(row)
        if self.record_bodies:
            self.body_pos.append(self.data.xpos.copy())
            self.body_quat.append(self.data.xquat.copy())
            self.tick_times.append(self.time)

    def run_until(self, done, max_seconds: float) -> bool:
        """Step until ``done()`` is true; False if ``max_seconds`` of simulated time passed first."""
        limit = self.ticks + int(np.ceil(max_seconds / self.dt_control))
        while not done():
            if self.ticks >= limit:
                return False
            self.step()
        return True
