"""Sequential execution, the paper's Algorithm 2 in the twin: one action at a time, each decided by AO* again
from the scene as the last one left it (decide, dispatch, complete, re-plan).

The session (:class:`~ergosim.twin.session.Session`) hands each repetition to its execution strategy; this
one is the default. A repetition is a generator that yields a :class:`DecisionPoint` whenever the next
(action, agent) is wanted, so that whoever drives it decides: the session's allocator in a run, a policy in
the Gym environment (:mod:`ergosim.gym`).
"""

from __future__ import annotations

from ergosim.errors import InfeasiblePlanError
from ergosim.twin.allocator import DecisionPoint
from ergosim.twin.records import attempt_status

__all__ = ["SequentialExecution"]


class SequentialExecution:
    """One action at a time (the paper's protocol): a failed attempt prunes as paper §2.2 says, the worker
    may refuse an offer (negotiation), and the repetition is abandoned when every agent that may do a
    remaining action failed at it."""

    name = "sequential"

    def attach(self, session) -> None:
        """Nothing to set up: the session's plant steps the acting robot alone."""

    def after_perform(self, session) -> None:
        """Nothing to restore after one action alone."""

    def finish(self, run):
        """The session's :class:`~ergosim.twin.records.SubjectRun`, as recorded (in decision order)."""
        return run

    def repetition(self, session, rep: int):
        """Repetition ``rep`` of ``session`` as a generator: it yields a :class:`DecisionPoint` whenever the
        next (action, agent) is wanted, receives the :class:`~ergosim.twin.allocator.Decision` (None:
        nothing is left), or an InfeasiblePlanError thrown in, and returns whether the repetition
        completed."""
        s = session
        plant, alloc = s.plant, s.allocator
        done: list[str] = []
        pruned: set[tuple[str, str]] = set()
        declined: set[tuple[str, str]] = set()  # refused by the worker for the decision being made
        attempts: dict[str, int] = {}
        order = 0
        while True:
            try:
                decision = yield DecisionPoint(plant.v, done, pruned | declined, plant.time, rep)
            except InfeasiblePlanError as err:
                # Every agent that may do a remaining action failed at it: the repetition cannot finish.
                s.abandon(rep, order, done, pruned, err.what)
                return False
            if decision is None:
                return True
            if s.refused(decision, rep, order, pruned | declined):
                declined.add((decision.action, decision.agent))
                order += 1
                continue
            declined.clear()
            s.decisions.append(decision)
            out = s.perform(decision.action, decision.agent)
            if out.ok:
                alloc.observe(decision.action, decision.agent, out.t_end - out.t_start)
            attempt = s.attempt(decision.action, rep)
            if out.ok:
                done.append(decision.operation)
                pruned.clear()
            else:
                s.record_failure(decision, rep, out)
                s.count_failure(decision, out, attempts, pruned)
            s.allocations.append(s.allocation(decision, rep, order, out.t_start, out.t_end,
                                              attempt_status(out), attempt))
            order += 1

