"""One subject's repetitions in one mode: decisions (Algorithm 2), dispatch, completion, takt.

The session owns the allocation logic of paper Fig. 1 and nothing physical: the plant steps the scene and
the ergonomics, the worker track supplies the worker's frames, the robot track drives the robots' skills.
"""

from __future__ import annotations

import dataclasses
import logging

import mujoco
import numpy as np

from ergosim import quat
from ergosim.errors import InfeasiblePlanError
from ergosim.scenes.build import weld_name
from ergosim.twin.allocator import Allocator, Decision, DecisionPoint
from ergosim.twin.in_hand import CarryHook, InHandTurn, relative_pose
from ergosim.twin.loop import Plant
from ergosim.twin.modes import get_mode
from ergosim.twin.protocol import SessionConfig
from ergosim.twin.records import Allocation, Failure, RepetitionOutcome, SubjectRun, attempt_status
from ergosim.twin.sequential import SequentialExecution
from ergosim.twin.ssm_monitor import SafetyMonitor
from ergosim.worker.motion import Worker

__all__ = ["Session", "Outcome", "DecisionPoint", "ACTION_TIMEOUT"]

log = logging.getLogger(__name__)

# Time allowed to any single action before it counts as failed [s of simulated time]; the slowest robot
# action at 0.05 m/s takes about 30 s, the slowest human action about 8 s.
ACTION_TIMEOUT = 180.0
# The worker retries a failed action from wherever the part now lies; after this many failures of one action
# in one repetition the worker's hyper-arc is pruned as well (the action is beyond what the worker can do).
_HUMAN_ATTEMPTS = 3


@dataclasses.dataclass(frozen=True)
class Outcome:
    """How one attempt at an action ended: ``ok`` when the scene's completion check of the action's kind
    passed; ``status`` ``ok`` or the failure (a robot skill's status, or the worker's ``unreachable (N cm
    short)``, ``not_completed``, ``timeout``); sim times [s]; ``message`` in words."""

    ok: bool
    status: str
    t_start: float
    t_end: float
    message: str = ""


class Session:
    """Runs ``repetitions`` of the task for one subject in one mode and returns a :class:`SubjectRun`.

    ``strategy``: how a repetition's actions are executed, the one object the session hands each repetition
    to (:meth:`run_steps`): the paper's one action at a time (:class:`SequentialExecution`, the default)
    or the team's parallel execution (:class:`~ergosim.twin.team_session.ParallelExecution`). Both use the
    session's public steps: :meth:`perform`, :meth:`worker_begin` / :meth:`worker_end`, :meth:`completed`
    and the records (:meth:`allocation`, :meth:`record_failure`, :meth:`count_failure`, :meth:`refused`,
    :meth:`abandon`)."""

    def __init__(self, *, cfg: SessionConfig, mode: str, subject_index: int, worker: Worker, plant: Plant,
                 robot, allocator: Allocator, rng: np.random.Generator, negotiator=None,
                 monitor: SafetyMonitor | None = None, strategy=None) -> None:
        self.cfg = cfg
        self.mode = mode
        self.subject_index = subject_index
        self.worker = worker
        self.plant = plant
        self.cell = plant.cell
        # the robots by name (the task's robot agents); one RobotTrack is the cell's only robot
        self.robots = dict(robot) if isinstance(robot, dict) else ({robot.name: robot} if robot else {})
        self.robot = next(iter(self.robots.values()), None)  # the one acting now
        self.allocator = allocator
        self.rng = rng
        self.hand = f"human_{worker.side}"
        self.allocations: list[Allocation] = []
        self.failures: list[Failure] = []
        self.outcomes: list[RepetitionOutcome] = []
        self.decisions: list[Decision] = []
        self.negotiator = negotiator
        """A :class:`~ergosim.twin.negotiation.Negotiator` when the worker may refuse, else None."""
        self.monitor = monitor
        """The plant's speed and separation monitor (one of its hooks), or None."""
        self.strategy = strategy if strategy is not None else SequentialExecution()
        self.strategy.attach(self)

    @property
    def execution(self) -> str:
        """``sequential`` or ``parallel``: the strategy's name."""
        return self.strategy.name

    # -- completion, detected in the scene -----------------------------------------------------------------
    def completed(self, geom) -> bool:
        """The scene's completion check of the action's kind (:meth:`Workcell.action_done`)."""
        return self.cell.action_done(geom)

    def _settle(self, geom, seconds: float = 1.0) -> bool:
        """Let a released part come to rest, then check completion (the scene decides, not a timer)."""
        return self.plant.run_until(lambda: self.completed(geom), seconds) or self.completed(geom)

    # -- the worker does an action -------------------------------------------------------------------------
    def _in_hand_turn(self, motion, geom, body: str) -> InHandTurn:
        """The weld target that brings ``body`` onto ``geom.target`` when the hand reaches its place pose."""
        cell = self.cell
        rate = motion.rate
        place = next(ph for ph in motion.phases if ph.name in ("place", "insert", "fasten"))
        start = int(np.ceil(motion.t_grasp * rate))
        end = min(int(np.ceil(place.start * rate)), len(motion.t) - 1)
        # Hand pose at the place frame, from the human's own kinematics.
        hand_p, hand_q = cell.human.segment_pose_at(motion.angles[end], cell.hand_bodies[self.hand],
                                                     motion.stances[end])
        tgt_p, tgt_q = cell.site_pose(geom.target)
        if body != geom.part:  # the whole assembly, held by one of its profiles: keep the profile's offset
            rel_p, rel_q = relative_pose(*cell.body_pose(geom.part), *cell.body_pose(body))
            q = np.empty(4)
            mujoco.mju_mulQuat(q, tgt_q, rel_q)
            tgt_p, tgt_q = tgt_p + quat.to_mat(tgt_q) @ rel_p, q
        pos1, quat1 = relative_pose(hand_p, hand_q, tgt_p, tgt_q)
        eq = cell.model.equality(weld_name(self.hand, body)).id
        return InHandTurn(cell.model, eq, pos1, quat1, start, end)

    def worker_begin(self, geom, handover: bool = False) -> Outcome | tuple[object, CarryHook]:
        """Plan the worker's motion for ``geom`` and start it, with the hook of the hand on the part: the
        motion and that hook, or a failed Outcome when the hand cannot reach the part."""
        plant, cell = self.plant, self.cell
        t0 = plant.time
        motion = self.worker.plan(cell, geom, self.rng, action=geom.action, handover=handover)
        if motion.reach_error > cell.config.grasp_tolerance:
            # The hand cannot get to the part from where the worker stands: the action is not done (and the
            # part is not dragged to the hand by the grasp weld).
            return Outcome(False, f"unreachable ({motion.reach_error * 100:.0f} cm short)", t0, plant.time)
        plant.track.start_action(motion)
        grasp_part = cell.grasp_body(geom.part) if geom.moves_assembly else geom.part
        carry = CarryHook(cell, self.hand, geom, grasp_part, self._in_hand_turn(motion, geom, grasp_part))
        plant.hooks.append(carry)
        return motion, carry

    def worker_end(self, carry: CarryHook) -> None:
        """The worker's motion is over: its hook goes, and what it carried collides again."""
        self.plant.hooks.remove(carry)
        self.cell.pass_through(carry.carried, False)

    def _worker_action(self, geom, handover: bool = False) -> Outcome:
        plant = self.plant
        t0 = plant.time
        begun = self.worker_begin(geom, handover)
        if isinstance(begun, Outcome):
            return begun
        motion, carry = begun
        try:
            finished = plant.run_until(lambda: not plant.track.busy, motion.duration + 1.0)
        finally:
            self.worker_end(carry)
        ok = finished and self._settle(geom, 0.5)
        status = "ok" if ok else ("timeout" if not finished else "not_completed")
        why = self.cell.why_not_done(geom) if status == "not_completed" else ""
        return Outcome(ok, status, t0, plant.time, why)

    # -- the robot does an action --------------------------------------------------------------------------
    def _robot_action(self, geom) -> Outcome:
        plant = self.plant
        t0 = plant.time
        self.robot.start(geom, plant)
        handover = geom.handover is not None
        if handover:
            arrived = plant.run_until(lambda: self.robot.waiting or self.robot.done, ACTION_TIMEOUT)
            if not arrived or self.robot.done:
                return self._robot_failure(t0)
            # The worker takes the part from the gripper and inserts it (paper §7.2, Fig. 8 bottom). The
            # action is done when the scene says the part is in place; the robot's retreat and way home go on
            # while the next action starts (a robot action waits for it, :meth:`perform`).
            out = self._worker_action(geom, handover=True)
            if not out.ok:
                plant.run_until(lambda: self.robot.done, ACTION_TIMEOUT)
            return Outcome(out.ok, out.status, t0, plant.time,
                            "" if out.ok else f"the worker did not complete the handover ({out.status})")
        if not plant.run_until(lambda: self.robot.done, ACTION_TIMEOUT):
            return Outcome(False, "timeout", t0, plant.time)
        if not self.robot.ok:
            return self._robot_failure(t0)
        if geom.seats:
            self.cell.seat(geom.part)
        ok = self._settle(geom, 1.0)
        return Outcome(ok, "ok" if ok else "not_completed", t0, plant.time,
                       "" if ok else f"the robot's skill ended, but {self.cell.why_not_done(geom)}")

    def _robot_failure(self, t0: float) -> Outcome:
        self.plant.run_until(lambda: self.robot.done, ACTION_TIMEOUT)
        return Outcome(False, self.robot.status_name, t0, self.plant.time, self.robot.message)

    def perform(self, action: str, agent: str) -> Outcome:
        """``agent`` does ``action`` now, from the scene as it is: the worker's planned motion (KWear counting
        it as the action, eq. 3) or the robot's skill, then the scene's completion check of the action's
        kind. Nothing is decided or recorded; :meth:`run` calls this for every decision."""
        try:
            geom = self.cell.actions[action]
            if agent != self.allocator.human:
                if self.robot is not None and not self.robot.done:  # on its way home from the last action
                    self.plant.run_until(lambda: self.robot.done, ACTION_TIMEOUT)
                self.robot = self.plant.robot = self.robots[agent]  # the plant steps the acting robot's skill
                return self._robot_action(geom)
            self.plant.kwear.start_action(action)
            try:
                return self._worker_action(geom)
            finally:
                self.plant.kwear.finish_action()  # the online α update of §5, when enabled
        finally:
            self.strategy.after_perform(self)

    # -- repetitions ---------------------------------------------------------------------------------------
    def _decide_all(self, steps):
        """Run the generator ``steps`` (of :meth:`run_steps`) to its end, the
        allocator answering every :class:`DecisionPoint`; returns what the generator returns."""
        try:
            point = next(steps)
            while True:
                try:
                    decision = self.allocator.decide(*point)
                except InfeasiblePlanError as err:
                    point = steps.throw(err)
                else:
                    point = steps.send(decision)
        except StopIteration as stop:
            return stop.value

    # -- the records of an attempt ---------------------------------------------------------------------------
    def attempt(self, action: str, rep: int) -> int:
        """The number of the next attempt at ``action`` in repetition ``rep`` (refusals do not count)."""
        return sum(a.action == action and a.status != "refused" for a in self.allocations
                   if a.repetition == rep) + 1

    def record_failure(self, decision: Decision, rep: int, out: Outcome) -> None:
        """The failure record of ``decision``'s failed attempt ``out``."""
        msg = (f"repetition {rep}: {decision.action} by {decision.agent} failed ({out.status}) "
               f"at t={out.t_end:.1f} s" + (f": {out.message}" if out.message else ""))
        self.failures.append(Failure(out.t_end, self.subject_index, self.mode, rep, decision.action,
                                     decision.agent, attempt_status(out), msg))
        log.debug("subject %d, %s: %s", self.subject_index, self.mode, msg)

    def count_failure(self, decision: Decision, out: Outcome, attempts: dict[str, int],
                      pruned: set[tuple[str, str]]) -> None:
        """Paper §2.2: a robot that cannot do an action loses its hyper-arc for this repetition and the
        planner re-plans without it; the worker retries from wherever the part now lies, and loses its own
        hyper-arc when it cannot reach the part or after :data:`_HUMAN_ATTEMPTS` failures."""
        attempts[decision.action] = attempts.get(decision.action, 0) + 1
        if (decision.agent != self.allocator.human or out.status.startswith("unreachable")
                or attempts[decision.action] >= _HUMAN_ATTEMPTS):
            pruned.add((decision.action, decision.agent))

    def allocation(self, decision: Decision, rep: int, order: int, t_start: float, t_end: float, status: str,
                   attempt: int) -> Allocation:
        alloc = self.allocator
        return Allocation(
            subject=self.subject_index, mode=self.mode, repetition=rep, order=order,
            action=decision.action, agent=decision.agent,
            human_cost=decision.cost_of(alloc.human), robot_cost=self._robot_cost(decision),
            t_start=t_start, t_end=t_end, had_choice=decision.had_choice, status=status, attempt=attempt,
            forced=self._forced(decision), allocatable=len(alloc.allowed[decision.action]) > 1,
        )

    def refused(self, decision: Decision, rep: int, order: int, cut: set[tuple[str, str]]) -> bool:
        """Negotiation: the worker, offered ``decision``'s action while another agent could take it, refuses
        it (a ``refused`` row is written); False without negotiation or when no one else could."""
        alloc = self.allocator
        if self.negotiator is None or decision.agent != alloc.human:
            return False
        others = alloc.allowed[decision.action] - {alloc.human} - {a for (act, a) in
                                                                   alloc.base_pruned | cut
                                                                   if act == decision.action}
        if not others:
            return False
        offer = self.negotiator.offer(self.plant.time, rep, decision.action)
        if not offer.refused:
            return False
        t = self.plant.time
        self.allocations.append(self.allocation(decision, rep, order, t, t, "refused",
                                                self.attempt(decision.action, rep)))
        return True

    def run(self, repetitions: int) -> SubjectRun:
        """``repetitions`` of the task, every decision the allocator's."""
        return self.strategy.finish(self._decide_all(self.run_steps(repetitions)))

    def run_steps(self, repetitions: int):
        """:meth:`run` as a generator of :class:`DecisionPoint` (see
        :meth:`~ergosim.twin.sequential.SequentialExecution.repetition`): whoever drives it decides (the Gym
        environment, :mod:`ergosim.gym`); returns the :class:`SubjectRun`."""
        plant, cfg = self.plant, self.cfg
        completed = overruns = 0
        # a takt-paced line starts every repetition at its takt slot (paper §7.2: "we fixed the takt time for
        # the two experimental conditions"); H-only workers wait for the takt whatever the line
        wait = cfg.pacing.takt_paced or get_mode(self.mode).waits_for_takt
        for rep in range(1, repetitions + 1):
            slot = (rep - 1) * cfg.pacing.takt
            if wait and plant.time < slot:
                plant.track.start_rest(slot - plant.time)
                plant.run_until(lambda s=slot: plant.time >= s - 1e-9, slot - plant.time + 1.0)
            self.cell.reset_parts()  # the second operator lays the parts out again (§7.2)
            plant.repetition = rep
            start = plant.time
            ok = yield from self.strategy.repetition(self, rep)
            completed += int(ok)
            overruns += int(plant.time - start > cfg.pacing.takt)
            if ok:
                self.outcomes.append(RepetitionOutcome(self.subject_index, self.mode, rep, "completed",
                                                       t_start=start, t_end=plant.time))
            else:
                self.outcomes[-1] = dataclasses.replace(self.outcomes[-1], t_start=start, t_end=plant.time)
                self.outcomes += [RepetitionOutcome(self.subject_index, self.mode, r, "not_run",
                                                    f"repetition {rep} was abandoned")
                                  for r in range(rep + 1, repetitions + 1)]
                break
        # The shift lasts the production schedule: a worker who finished early rests until its end, so
        # the load proxies of every mode cover the same window (paper §7.2: takt-timed repetitions).
        horizon = repetitions * cfg.pacing.takt
        if plant.time < horizon:
            plant.track.start_rest(horizon - plant.time)
            plant.run_until(lambda: plant.time >= horizon - 1e-9, horizon - plant.time + 1.0)
        bodies = None
        if plant.record_bodies:
            bodies = (np.array(plant.body_pos), np.array(plant.body_quat))
        safety = self.monitor.record(plant) if self.monitor is not None else None
        if safety is not None and safety.end_separation <= 0:
            self.failures.append(Failure(plant.time, self.subject_index, self.mode, repetitions, "", "",
                                         "robot_in_worker", f"the run ended with a robot inside the worker "
                                         f"(separation {safety.end_separation * 100:.1f} cm)"))
        return SubjectRun(
            subject=self.subject_index, mode=self.mode, allocations=self.allocations, ticks=plant.log,
            repetitions_completed=completed, takt_overruns=overruns, dt_tick=plant.dt_tick,
            v_th=cfg.cost.v_th,
            failures=self.failures, decisions=self.decisions, bodies=bodies, horizon=horizon,
            outcomes=self.outcomes, human=self.allocator.human, robots=tuple(self.allocator.robots),
            execution=self.execution,
            offers=list(self.negotiator.offers) if self.negotiator is not None else [],
            safety=safety,
            robot_spans=[(name, t0, t0 + r.duration, r.phase("wait")) for name, track in self.robots.items()
                         for t0, r in zip(track.started, track.results)],
        )

    # -- what the outputs say about an attempt -------------------------------------------------------------
    def _robot_cost(self, decision: Decision) -> float:
        """The cost of the robot that got the action, else of the cheapest robot (NaN without costs)."""
        alloc = self.allocator
        if decision.agent in alloc.robots:
            return decision.cost_of(decision.agent)
        costs = [decision.cost_of(r) for r in alloc.robots]
        return min(costs, key=lambda c: (np.isnan(c), c)) if costs else float("nan")

    def _forced(self, decision: Decision) -> str:
        """The agent, if the task and mode allow more than one agent for the action but failures in this
        repetition pruned every other one; else ""."""
        alloc = self.allocator
        action = decision.action
        by_mode = alloc.allowed[action] - {a for (act, a) in alloc.base_pruned if act == action}
        return decision.agent if len(by_mode) > 1 and not decision.had_choice else ""

    def abandon(self, rep: int, order: int, done: list[str], pruned: set[tuple[str, str]], why: str) -> None:
        """Record an abandoned repetition: a ``pruned`` row per action whose every allowed agent failed."""
        alloc, t = self.allocator, self.plant.time
        msg = f"repetition {rep}: abandoned, {why}"
        log.debug("subject %d, %s: %s", self.subject_index, self.mode, msg)
        self.failures.append(Failure(t, self.subject_index, self.mode, rep, "", "", "abandoned", msg))
        self.outcomes.append(RepetitionOutcome(self.subject_index, self.mode, rep, "abandoned", why))
        done_actions = {alloc.action_of(o) for o in done}
        cut = alloc.base_pruned | pruned
        for action in alloc.graph.actions:
            agents = alloc.allowed[action]
            if action in done_actions or not all((action, a) in cut for a in agents):
                continue
            attempts = self.attempt(action, rep) - 1
            self.allocations.append(Allocation(
                subject=self.subject_index, mode=self.mode, repetition=rep, order=order, action=action,
                agent="", human_cost=np.nan, robot_cost=np.nan, t_start=t, t_end=t, had_choice=False,
                status="pruned", attempt=attempts, allocatable=len(agents) > 1,
            ))
            order += 1
