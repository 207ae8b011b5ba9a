"""``ergosim/Allocation-v0``: role allocation as a Gymnasium environment, stepping the twin's own loop.

An episode is one subject's run of a scenario: N repetitions of the task in its workcell, the subject
calibrated first (§5) as ``ergosim run`` calibrates it. A step is one allocation decision: the policy picks an
(action, agent); the session performs it in MuJoCo exactly as in ``ergosim run`` (the worker's motion, KWear
per tick, the robot's skill, the scene's completion check, failures and their pruning, the takt, the rest
until the shift ends) up to the next decision. The session is the one ``ergosim run`` uses
(:meth:`~ergosim.twin.session.Session.run_steps`), so a policy that decides as a mode's allocator reproduces
that mode's run allocation for allocation.

Observation (a ``Dict``, float32 and int8):

- ``v`` (5,): the worker's KWear V per joint now (shoulder, elbow, wrist, trunk, neck; eq. 3-5);
- ``v_hat`` (A, 5): V̂ after each action from V now (eq. 9; 0 for actions done);
- ``done`` (A,), ``available`` (A,): the actions done in this repetition, and those that can start now;
- ``takt_time`` (1,): time since the repetition started, as a fraction of the takt (1 = the takt is over);
- ``action_mask`` (A·N,): which (action, agent) choices are valid now (also ``info["action_mask"]``).

Action: ``Discrete(A·N)``, index = action index × N + agent index, in the task's ``actions`` and ``agents``
order (``env.unwrapped.choices`` lists them). A masked choice changes nothing and earns
``-invalid_penalty``.

Reward of a step: minus the KWear integral over the step, ∫ Σ_i V_i dt [s], the load proxy of §7.2, minus
``takt_penalty`` × the seconds of the step's action past the repetition's takt. The default penalty, 5 per
second, is the largest rate the integral itself can reach (all five joints at V = 1): a second past the takt
weighs as much as the worst second of wear.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ergosim import api
from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.experiment.subject import rig_spec, scenario_subject
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.rig import calibrated, ready_session

__all__ = ["AllocationEnv", "TAKT_PENALTY"]

TAKT_PENALTY = float(len(KWEAR_JOINTS))
"""Reward per second past the takt: the integral's largest rate (every joint at V = 1)."""


class AllocationEnv(gym.Env):
    """One subject's run of ``scenario`` (a bundled name, a scenario file, or a loaded
    :class:`~ergosim.experiment.scenario.Scenario`) with ``overrides`` (``--set`` keys) and ``repetitions``
    (default the scenario's). ``subject``: the subject of the seed's population
    (``reset(options={"subject": i})`` changes it). ``mode``: the mode whose risk index prices ``v_hat`` and
    whose allocator :meth:`mode_action` consults; it also labels the records. ``reset(seed=s)`` draws the
    population of ``ergosim run --seed s``."""

    metadata = {"render_modes": []}

    def __init__(self, scenario: Any = "multi-subject", *, subject: int = 0, repetitions: int | None = None,
                 overrides: Mapping[str, Any] | None = None, mode: str = "hrc",
                 takt_penalty: float = TAKT_PENALTY, invalid_penalty: float = 1.0) -> None:
        self.scenario = scenario if hasattr(scenario, "protocol") else api.load(scenario, overrides)
        cfg = self.scenario.protocol
        if cfg.team.execution != "sequential":
            raise ConfigError("Allocation-v0 steps one decision at a time: execution must be sequential, got "
                              f"{cfg.team.execution!r}", where="AllocationEnv")
        if not (math.isfinite(takt_penalty) and takt_penalty >= 0 and math.isfinite(invalid_penalty)
                and invalid_penalty >= 0):
            raise ConfigError("takt_penalty and invalid_penalty must be finite and >= 0",
                              where="AllocationEnv")
        self.mode = mode
        self.subject = int(subject)
        self.repetitions = int(repetitions or cfg.pacing.repetitions)
        if self.repetitions < 1:
            raise ConfigError(f"repetitions must be >= 1, got {self.repetitions}", where="AllocationEnv")
        self.takt_penalty = float(takt_penalty)
        self.invalid_penalty = float(invalid_penalty)
        graph = self.scenario.task()
        self.actions = tuple(graph.actions)
        self.agents = tuple(a.name for a in graph.agents)
        self.choices = tuple((a, g) for a in self.actions for g in self.agents)
        """The (action, agent) of each action index."""
        n_a = len(self.actions)
        self.action_space = spaces.Discrete(len(self.choices))
        self.observation_space = spaces.Dict({
            "v": spaces.Box(0.0, 1.0, (len(KWEAR_JOINTS),), np.float32),
            "v_hat": spaces.Box(0.0, 1.0, (n_a, len(KWEAR_JOINTS)), np.float32),
            "done": spaces.MultiBinary(n_a),
            "available": spaces.MultiBinary(n_a),
            "takt_time": spaces.Box(0.0, np.finfo(np.float32).max, (1,), np.float32),
            "action_mask": spaces.MultiBinary(len(self.choices)),
        })
        self._spec = rig_spec(self.scenario)
        self._calibrated: dict[tuple[int, int], tuple] = {}
        self.session = None
        self.result = None
        """The :class:`~ergosim.twin.records.SubjectRun` once the episode has ended."""

    # -- episode ------------------------------------------------------------------------------------------
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        options = options or {}
        self.subject = int(options.get("subject", self.subject))
        self.seed = int(seed) if seed is not None else int(self.np_random.integers(2**31 - 1))
        key = (self.seed, self.subject)
        subject = scenario_subject(self.scenario, self.subject, self.seed)
        if key not in self._calibrated:  # deterministic in (seed, subject): calibrate once
            self._calibrated[key] = calibrated(self._spec, subject, self.subject, self.seed)
        self.session = ready_session(self._spec, subject, self.subject, self.seed, self.mode,
                                     calibrated_as=self._calibrated[key])
        self.result = None
        self._steps = self.session.run_steps(self.repetitions)
        self._rep_start = {}
        self._advance(next(self._steps))
        return self._observation(), self._info()

    def step(self, action):
        if self.session is None or self.result is not None:
            raise gym.error.ResetNeeded("call reset() before step() (the episode has ended)")
        mask = self._mask()
        index = int(action)
        if not (0 <= index < len(self.choices)) or not mask[index]:
            info = self._info(mask)
            info["invalid_action"] = True
            return self._observation(mask), -self.invalid_penalty, False, False, info
        return self._perform(*self.choices[index])

    def mode_action(self) -> int:
        """The choice the env's mode's own allocator makes now (``hrc``: the paper's rule;
        ``kwear-lookahead``: the look-ahead), as an action index; -1 when it finds none (the repetition
        cannot be finished)."""
        decision = self._decide()
        return -1 if decision is None else self.choices.index((decision.action, decision.agent))

    # -- inside ---------------------------------------------------------------------------------------------
    def _decide(self):
        p = self._point
        try:
            return self.session.allocator.decide(p.v_now, p.done, p.pruned, p.time, p.repetition)
        except InfeasiblePlanError:
            return None

    def _perform(self, action: str, agent: str):
        session, point = self.session, self._point
        plant = session.plant
        decision = session.allocator.chosen(action, agent, point.v_now, point.done, point.pruned, point.time,
                                            point.repetition)
        start_row, rows_before = plant.log.n, len(session.allocations)
        deadline = self._rep_start[point.repetition] + session.cfg.pacing.takt
        try:
            point = self._steps.send(decision)
        except StopIteration as stop:
            self.result = stop.value
        else:
            self._advance(point)
        kwear = plant.log.kwear[start_row:]
        integral = float(kwear.sum()) * plant.dt_tick
        late = sum(max(0.0, a.t_end - max(a.t_start, deadline)) for a in session.allocations[rows_before:]
                   if a.repetition == point.repetition)
        reward = -integral - self.takt_penalty * late
        info = self._info()
        info.update(kwear_integral=integral, late_s=late,
                    allocation=[a for a in session.allocations[rows_before:]])
        return self._observation(), reward, self.result is not None, False, info

    def _advance(self, point) -> None:
        """Move to the next decision a policy has to make: a repetition whose actions are all done is
        closed (the allocator's None), one in which no pair is left is abandoned (its InfeasiblePlanError),
        as the session's own loop does."""
        steps, alloc = self._steps, self.session.allocator
        try:
            while True:
                if point.repetition not in self._rep_start:
                    self._rep_start[point.repetition] = point.time
                done = {alloc.action_of(o) for o in point.done}
                if done >= set(self.actions):
                    point = steps.send(None)
                elif not alloc.ready(point.done, point.pruned):
                    point = steps.throw(InfeasiblePlanError(
                        "no feasible plan: no agent is left for the remaining actions"))
                else:
                    break
            self._point = point
        except StopIteration as stop:
            self.result = stop.value

    def _mask(self) -> np.ndarray:
        mask = np.zeros(len(self.choices), dtype=np.int8)
        if self.result is not None:
            return mask
        p = self._point
        for key in self.session.allocator.ready(p.done, p.pruned):
            mask[self.choices.index(key)] = 1
        return mask

    def _observation(self, mask: np.ndarray | None = None) -> dict:
        mask = self._mask() if mask is None else mask
        n_a, n_g = len(self.actions), len(self.agents)
        p = self._point
        alloc = self.session.allocator
        done_actions = {alloc.action_of(o) for o in p.done} if self.result is None else set(self.actions)
        done = np.array([a in done_actions for a in self.actions], dtype=np.int8)
        v_hat = np.zeros((n_a, len(KWEAR_JOINTS)), dtype=np.float32)
        index = self.session.plant.kwear
        for i, a in enumerate(self.actions):
            if not done[i]:
                v_hat[i] = index.predict(a)
        elapsed = 0.0 if self.result is not None else p.time - self._rep_start[p.repetition]
        return {
            "v": np.asarray(self.session.plant.v, dtype=np.float32).copy(),
            "v_hat": np.clip(v_hat, 0.0, 1.0),
            "done": done,
            "available": mask.reshape(n_a, n_g).max(axis=1).astype(np.int8),
            "takt_time": np.array([elapsed / self.session.cfg.pacing.takt], dtype=np.float32),
            "action_mask": mask,
        }

    def _info(self, mask: np.ndarray | None = None) -> dict:
        p = self._point
        return {"action_mask": self._mask() if mask is None else mask, "time": float(p.time),
                "repetition": int(p.repetition), "seed": self.seed, "subject": self.subject}
