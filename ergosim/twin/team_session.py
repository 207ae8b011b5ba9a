"""Parallel execution: the worker and the robots work at the same time (issue 17).

Whenever an agent is idle, the team allocator (:mod:`ergosim.twin.team_allocator`) gives it the best
operation ready now: its children exist, nobody holds them, and precedence is met (the AND/OR graph says
so). The robot fetches and presents the next profile while the worker inserts the current one; in the
gearbox cell two sub-assemblies are built at once. A robot's handover holds only the part it fetches; at
the handover pose the robot waits until the worker is free, and the worker serves a waiting robot before
anything new (synchronisation). :class:`ParallelExecution` is the session's strategy for a repetition
(composition: it drives the :class:`~ergosim.twin.session.Session`'s public steps); everything else is the
session's, as in sequential execution: the plant,
the worker's motion with its grasp and release hooks, the robots' skills, the scene's completion checks,
the failure rules (a robot that fails loses its hyper-arc for the repetition; the worker retries, at most
three times), the takt, the records.

The session is a small event loop over one plant: it steps the physics tick by tick, advances every job
(the worker's action, each robot's skill, the settling of released parts), and decides again whenever a
job ends or an agent becomes idle. Several robots step together (:class:`RobotGroup`).
"""

from __future__ import annotations

import dataclasses
import math
from itertools import count

import numpy as np

from ergosim.errors import InfeasiblePlanError
from ergosim.twin.allocator import Decision
from ergosim.twin.modes import get_mode
from ergosim.twin.records import attempt_status
from ergosim.twin.robot_track import RobotGroup, RobotTrack
from ergosim.twin.session import ACTION_TIMEOUT, Outcome
from ergosim.twin.standoff import StandoffWatch
from ergosim.twin.team_allocator import Busy, TeamAllocator
from ergosim.twin.team_board import TeamBoard

__all__ = ["ParallelExecution", "handover_early"]

_WORKER_SETTLE = 0.5  # s a part the worker released may take to come to rest (as the sequential session)
_ROBOT_SETTLE = 1.0


@dataclasses.dataclass
class _Job:
    """One agent at work: the worker's action (own, or taking a handed part: ``serves`` the robot's job),
    or a robot's skill. ``state``: worker ``acting``/``settling``; robot ``moving``/``settling`` (place,
    insert, fasten), ``fetching``/``waiting``/``taken``/``homing`` (handover), ``failing`` (waiting for the
    robot to come home after a failure)."""

    id: int
    agent: str
    geom: object
    decision: Decision | None
    t0: float
    order: int
    attempt: int
    repetition: int
    state: str
    carried: np.ndarray | None = None
    deadline: int = 0
    settle_until: int = 0
    serves: _Job | None = None
    track: RobotTrack | None = None
    take: _Job | None = None
    outcome: Outcome | None = None


def handover_early(cell, allowed, robots) -> dict[tuple[str, str], str]:
    """(action, robot) -> moving part, for every action a robot does by handing the part over: the robot
    holds only that part until the worker takes it."""
    return {(action, r): cell.actions[action].part for action, agents in allowed.items()
            if cell.actions[action].handover is not None for r in robots if r in agents}


class ParallelExecution:
    """The execution strategy of a :class:`~ergosim.twin.session.Session` with parallel execution: every
    idle agent starts the best operation ready now. ``margin``: the team allocator's (``team_margin`` of the
    protocol; None: Γ of the mode). It drives the session's public steps; its own state is the jobs."""

    name = "parallel"

    def __init__(self, margin: float | None = None) -> None:
        self.margin = margin
        self.s = None
        self.worker_job: _Job | None = None
        self.robot_jobs: dict[str, _Job] = {}

    def attach(self, session) -> None:
        """Build the mode's team allocator on the session's, and let the plant step the robots together."""
        self.s = session
        alloc = session.allocator
        build = get_mode(session.mode).team_allocator or TeamAllocator
        self.team = build(alloc, early=handover_early(session.cell, alloc.allowed, alloc.robots),
                          margin=self.margin)
        session.plant.robot = RobotGroup(session.robots.values())
        self._ids = count()

    def after_perform(self, session) -> None:
        """After one action alone (:meth:`Session.perform`), the robots step together again."""
        session.plant.robot = RobotGroup(session.robots.values())

    def finish(self, run):
        """The run's allocation rows in decision order (jobs end out of order)."""
        run.allocations.sort(key=lambda a: (a.repetition, a.order))
        return run

    # -- one repetition --------------------------------------------------------------------------------------
    def repetition(self, session, rep: int):
        """The team decides inside the repetition's event loop: nothing is yielded to the caller."""
        return self._repetition(rep)
        yield  # pragma: no cover - makes this a generator

    def _repetition(self, rep: int) -> bool:
        self.board = TeamBoard(self.s.allocator.graph, self.team.early)
        self._rep = rep
        self._pruned: set[tuple[str, str]] = set()
        self._attempts: dict[str, int] = {}
        self._order = 0
        self._dirty = True
        self._standoff = StandoffWatch()
        while True:
            if self._dirty:
                self._dirty = False
                if not self._dispatch(rep):
                    return False
                if self._complete():
                    return True
            self.s.plant.step()
            self._poll()
            why = self._standoff.check(self.s.plant, self.worker_job is None, self.robot_jobs.values())
            if why is not None:
                self._end_standoff(rep, why)
                return False

    def _complete(self) -> bool:
        holding = [j for j in self.robot_jobs.values() if j.state not in ("homing",)]
        return self.board.complete and self.worker_job is None and not holding

    def _idle(self) -> list[str]:
        alloc = self.s.allocator
        idle = [alloc.human] if self.worker_job is None else []
        return idle + [r for r in alloc.robots if r not in self.robot_jobs and self.s.robots[r].done]

    def _dispatch(self, rep: int) -> bool:
        """Start what can start now; False when the repetition is abandoned."""
        plant = self.s.plant
        while True:
            if self.worker_job is None:
                self._serve_handover(rep)
            idle = self._idle()
            if not idle or self.board.complete:
                return True
            declined: set[tuple[str, str]] = set()
            for guard in (True, False):
                while True:
                    try:
                        picks = self.team.decide(plant.v, self.board, idle, self._pruned | declined,
                                                 plant.time, rep, guard=guard, busy=self._busy())
                    except InfeasiblePlanError as err:
                        if self._active():
                            return True  # something still running may free what is missing
                        self.s.abandon(rep, self._order, self.board.done, self._pruned, err.what)
                        return False
                    refused = next((d for d, _ in picks if self.s.refused(d, rep, self._order,
                                                                       self._pruned | declined)), None)
                    if refused is None:
                        break
                    declined.add((refused.action, refused.agent))
                    self._order += 1
                if picks or self._active():
                    break
            if not picks:
                if self._active():
                    return True
                self.s.abandon(rep, self._order, self.board.done, self._pruned,
                              "no agent can start any remaining operation")
                return False
            started_instantly_failed = False
            for decision, step in picks:
                started_instantly_failed |= not self._start(decision, step, rep)
            if not started_instantly_failed:
                return True

    def _busy(self) -> list[Busy]:
        """The agents at work, for decisions that look at time."""
        jobs = ([self.worker_job] if self.worker_job is not None else []) + list(self.robot_jobs.values())
        return [Busy(j.agent, j.geom.action, j.t0, j.state, take=j.serves is not None,
                     robot=j.serves.agent if j.serves is not None else None) for j in jobs]

    def _active(self) -> bool:
        """Some agent is at work, or a robot is on its way home (it is free again soon): wait for it rather
        than give up or give an agent what the plan keeps from it."""
        return self.worker_job is not None or bool(self.robot_jobs)

    # -- starting jobs ---------------------------------------------------------------------------------------
    def _start(self, decision: Decision, step, rep: int) -> bool:
        """Start ``decision``; False if it failed at once (a worker who cannot reach the part)."""
        alloc, plant = self.s.allocator, self.s.plant
        self.s.decisions.append(decision)
        geom = self.s.cell.actions[decision.action]
        attempt = self.s.attempt(decision.action, rep)
        job = _Job(next(self._ids), decision.agent, geom, decision, plant.time, self._order, attempt, rep, "")
        self._order += 1
        self.board.start(job.id, step)
        if decision.agent == alloc.human:
            plant.kwear.start_action(decision.action)
            return self._start_worker(job, handover=False)
        track = self.s.robots[decision.agent]
        track.start(geom, plant)
        job.track = track
        job.state = "fetching" if geom.handover is not None else "moving"
        job.deadline = plant.ticks + int(math.ceil(ACTION_TIMEOUT / plant.dt_control))
        self.robot_jobs[decision.agent] = job
        return True

    def _start_worker(self, job: _Job, handover: bool) -> bool:
        plant = self.s.plant
        begun = self.s.worker_begin(job.geom, handover)
        self.worker_job = job
        if isinstance(begun, Outcome):
            self._finish_worker(job, begun)
            return False
        motion, job.carried = begun
        job.state = "acting"
        job.deadline = plant.ticks + int(math.ceil((motion.duration + 1.0) / plant.dt_control))
        return True

    def _serve_handover(self, rep: int) -> None:
        """The idle worker takes the part of the robot that has waited longest at the handover pose."""
        waiting = sorted((j for j in self.robot_jobs.values() if j.state == "waiting"), key=lambda j: j.t0)
        for robot_job in waiting:
            take = _Job(next(self._ids), self.s.allocator.human, robot_job.geom, None, self.s.plant.time,
                        robot_job.order, robot_job.attempt, robot_job.repetition, "", serves=robot_job)
            if self.board.join(take.id, robot_job.geom.action) is None:
                continue  # what the part goes into is not there, or is held: the robot keeps waiting
            robot_job.state, robot_job.take = "taken", take
            self._start_worker(take, handover=True)
            return

    # -- advancing jobs --------------------------------------------------------------------------------------
    def _poll(self) -> None:
        if self.worker_job is not None:
            self._poll_worker(self.worker_job)
        for job in list(self.robot_jobs.values()):
            self._poll_robot(job)

    def _poll_worker(self, job: _Job) -> None:
        plant = self.s.plant
        if job.state == "acting":
            if plant.track.busy:
                if plant.ticks >= job.deadline:
                    self.s.worker_end(job.carried)
                    self._finish_worker(job, Outcome(False, "timeout", job.t0, plant.time))
                return
            self.s.worker_end(job.carried)
            job.state = "settling"
            job.settle_until = plant.ticks + int(math.ceil(_WORKER_SETTLE / plant.dt_control))
        if job.state == "settling":
            if self.s.completed(job.geom):
                self._finish_worker(job, Outcome(True, "ok", job.t0, plant.time))
            elif plant.ticks >= job.settle_until:
                self._finish_worker(job, Outcome(False, "not_completed", job.t0, plant.time,
                                                 self.s.cell.why_not_done(job.geom)))

    def _poll_robot(self, job: _Job) -> None:
        plant, track = self.s.plant, job.track
        state = job.state
        if state == "homing":
            if track.done:
                self._free_robot(job)
        elif state == "failing":
            if track.done:
                self._record(job, job.outcome)
                self.board.drop(action=job.geom.action)
                self._free_robot(job)
        elif state in ("fetching", "waiting"):
            if track.done:  # failed before the worker took the part (or nobody took it in time)
                self.board.drop(action=job.geom.action)
                self._record(job, Outcome(False, track.status_name, job.t0, plant.time, track.message))
                self._free_robot(job)
            elif state == "fetching" and track.waiting:
                job.state = "waiting"
                self._dirty = True
        elif state == "moving":
            if track.done or track.released:
                # Let go, the part is where it goes: the operation ends there and the robot's way home goes
                # on while the next one starts (as after a handover's take).
                if track.done and not track.ok:
                    self._robot_outcome(job, Outcome(False, track.status_name, job.t0, plant.time,
                                                     track.message))
                    return
                if job.geom.seats:
                    self.s.cell.seat(job.geom.part)
                job.state = "settling"
                job.settle_until = plant.ticks + int(math.ceil(_ROBOT_SETTLE / plant.dt_control))
            elif plant.ticks >= job.deadline:
                self._robot_outcome(job, Outcome(False, "timeout", job.t0, plant.time))
                return
        if job.state == "settling":
            if self.s.completed(job.geom):
                self._robot_outcome(job, Outcome(True, "ok", job.t0, plant.time))
            elif plant.ticks >= job.settle_until:
                why = f"the robot's skill ended, but {self.s.cell.why_not_done(job.geom)}"
                self._robot_outcome(job, Outcome(False, "not_completed", job.t0, plant.time, why))

    # -- a standoff ------------------------------------------------------------------------------------------
    def _end_standoff(self, rep: int, why: str) -> None:
        """The repetition ends in a standoff: every robot job whose action is not recorded yet fails
        (``standoff``), then the repetition is abandoned with ``why``."""
        t = self.s.plant.time
        for job in list(self.robot_jobs.values()):
            if job.state in ("moving", "settling", "fetching", "waiting"):
                self.board.drop(job=job.id, action=job.geom.action)
                self._record(job, Outcome(False, "standoff", job.t0, t, why))
        self.s.abandon(rep, self._order, self.board.done, self._pruned, why)

    # -- ending jobs -----------------------------------------------------------------------------------------
    def _finish_worker(self, job: _Job, out: Outcome) -> None:
        self.worker_job = None
        self._dirty = True
        if job.serves is None:
            self.s.plant.kwear.finish_action()  # the online α update of §5, when enabled
            if out.ok:
                self.board.finish(job.id)
            else:
                self.board.drop(job=job.id)
            self._record(job, out)
            return
        robot_job = job.serves
        if out.ok:
            self.board.finish(job.id)
            robot_job.state = "homing"  # the robot's way home goes on while the next action starts
            self._record(robot_job, Outcome(True, "ok", robot_job.t0, self.s.plant.time))
            if robot_job.track.done:
                self._free_robot(robot_job)
        else:
            self.board.drop(job=job.id)
            self.board.reserved[robot_job.geom.action] = (robot_job.agent, robot_job.geom.part)
            robot_job.state = "failing"
            robot_job.outcome = Outcome(False, out.status, robot_job.t0, self.s.plant.time,
                                        f"the worker did not complete the handover ({out.status})")

    def _robot_outcome(self, job: _Job, out: Outcome) -> None:
        """A place, insertion or fastening by a robot ended (the part let go; the robot may still be on its
        way home, and is free once its skill is over)."""
        if out.ok:
            self.board.finish(job.id)
        else:
            self.board.drop(job=job.id)
        self._record(job, out)
        self._dirty = True  # what the operation held is free: decide again
        if job.track.done:
            self._free_robot(job)
        else:  # on its way home after the release, or a timeout: not free before its skill ends
            job.state = "homing"

    def _free_robot(self, job: _Job) -> None:
        self.robot_jobs.pop(job.agent, None)
        self._dirty = True

    def _record(self, job: _Job, out: Outcome) -> None:
        """The allocation row of ``job``'s decision, and on failure the failure record and the pruning of
        the sequential session (paper §2.2)."""
        decision, rep, alloc = job.decision, job.repetition, self.s.allocator
        t_end = out.t_end
        if out.ok and job.geom.handover is None:  # a handover's span includes its wait for the worker
            alloc.observe(decision.action, decision.agent, t_end - job.t0)
        if not out.ok:
            self.s.record_failure(decision, rep, out)
            if rep == self._rep:  # a robot back from a failure after its repetition ended prunes nothing
                self.s.count_failure(decision, out, self._attempts, self._pruned)
        self.s.allocations.append(self.s.allocation(decision, rep, job.order, job.t0, t_end,
                                                    attempt_status(out), job.attempt))
