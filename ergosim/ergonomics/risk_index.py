"""Risk indices: the extension point that decouples the framework from KWear (paper §5).

A :class:`RiskIndex` is advanced once per ergonomics tick with the RULA part scores G (5,) of the latest
frame and predicts, for each candidate action, the risk the cost model (eq. 10-11) turns into a
hyper-arc cost. Two implementations: :class:`KWearIndex` (eq. 3-9 with calibrated alphas) and
:class:`StaticRulaIndex` (the paper's static RULA baseline, a constant G(a_k) per action).

Dropouts: a tick whose G row has a non-finite entry is counted in ``dropouts`` and, while the worker acts,
leaves the state unchanged, so a NaN can never enter V. While resting, recovery needs no G and proceeds.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Iterable, Mapping

import numpy as np

from ergosim.ergonomics.calibration import online_alpha
from ergosim.ergonomics.kwear import KWearParams, kwear_step, predict
from ergosim.errors import ConfigError
from ergosim.posture import KWEAR_JOINTS

__all__ = ["RiskIndex", "KWearIndex", "StaticRulaIndex"]

_M = len(KWEAR_JOINTS)


class RiskIndex(ABC):
    """Per-worker ergonomic risk state, advanced per tick and predicted per candidate action.

    ``value``: (5,) current value per joint (KWEAR_JOINTS order). :meth:`predict` returns the
    (p,) predicted risk the cost model sums (eq. 11), with ``channels`` naming its p entries; the cost
    threshold V_th is compared with these numbers. Subclasses implement :meth:`_advance`, :meth:`predict`
    and :meth:`_reset`; the base class handles dropouts and counting.
    """

    joints: tuple[str, ...] = KWEAR_JOINTS
    channels: tuple[str, ...] = KWEAR_JOINTS
    scale: float = 1.0
    """A predicted value × ``scale`` is the index's own unit, for display (the static RULA index: G_max)."""

    def __init__(self) -> None:
        self._v = np.zeros(_M)
        self.ticks = 0
        self.dropouts = 0

    @property
    def value(self) -> np.ndarray:
        """(5,) current value per joint (a read-only view)."""
        v = self._v.view()
        v.flags.writeable = False
        return v

    def update(self, g, dt: float, resting: bool = False) -> np.ndarray:
        """Advance one tick of ``dt`` [s] with G (5,) part scores; ``resting`` True while the worker is not
        executing an action. A non-finite G row is a dropout: counted, and while acting V holds."""
        self.ticks += 1
        g = np.asarray(g, dtype=float)
        finite = bool(np.isfinite(g).all())
        if not finite:
            self.dropouts += 1
        if resting or finite:
            self._advance(g, dt, bool(resting))
        return self.value

    def predict_many(self, actions: Iterable[str]) -> np.ndarray:
        """(n_actions, p) predictions from the current state."""
        return np.array([self.predict(a) for a in actions]).reshape(-1, len(self.channels))

    def start_action(self, action: str) -> None:
        """Hook: the worker starts executing ``action`` (used by online parameter updates)."""

    def finish_action(self) -> None:
        """Hook: the action started with :meth:`start_action` is complete."""

    def reset(self, v0=None) -> None:
        """Back to zero (or ``v0`` (5,)) state; counters restart."""
        self._v[:] = 0.0 if v0 is None else np.asarray(v0, dtype=float)
        self.ticks = 0
        self.dropouts = 0
        self._reset()

    def _reset(self) -> None:
        """Subclass state to clear on :meth:`reset`."""

    @abstractmethod
    def _advance(self, g: np.ndarray, dt: float, resting: bool) -> None:
        """Advance the state by ``dt``; ``g`` is finite unless ``resting``."""

    @abstractmethod
    def predict(self, action: str) -> np.ndarray:
        """(p,) predicted risk after executing ``action`` from the current state."""


def _alpha_table(alphas: Mapping[str, object]) -> dict[str, np.ndarray]:
    out = {}
    for a, x in alphas.items():
        arr = np.array(x, dtype=float)
        if arr.shape != (_M,) or not np.all((arr > 0) & (arr <= 1)):
            raise ConfigError(f"alpha of action {a!r} must be {_M} values in (0, 1], got {x!r}",
                              where=f"KWearIndex.alphas[{a!r}]")
        out[a] = arr
    return out


class KWearIndex(RiskIndex):
    """KWear per joint (eq. 3-5) and its prediction V_hat = 1 - alpha (1 - V) (eq. 9).

    alphas: action -> (5,) calibrated alpha (:mod:`ergosim.ergonomics.calibration`).
    online_weight: weight of the latest execution in the online alpha average (paper §5); 0 (default, as
    in the paper's experiments) keeps the calibrated alphas. The executed action's alpha is
    exp(-int |G| dt / C) over its acting ticks (independent of V at its start, eq. 4).
    """

    def __init__(self, params: KWearParams, alphas: Mapping[str, object], online_weight: float = 0.0,
                 v0=None) -> None:
        super().__init__()
        if not 0.0 <= online_weight <= 1.0:
            raise ConfigError(f"online_weight must be in [0, 1], got {online_weight}", where="KWearIndex")
        self.params = params
        self.alphas = _alpha_table(alphas)
        self.online_weight = float(online_weight)
        self._action: str | None = None
        self._integral = np.zeros(_M)
        if v0 is not None:
            self._v[:] = v0

    @classmethod
    def from_worker(cls, worker, online_weight: float = 0.0) -> KWearIndex:
        """From :class:`~ergosim.ergonomics.param_store.WorkerParams`."""
        return cls(worker.kwear, worker.alphas, online_weight)

    def _advance(self, g: np.ndarray, dt: float, resting: bool) -> None:
        kwear_step(self._v, g, dt, self.params, resting=resting, out=self._v)
        if self._action is not None and not resting:
            self._integral += np.abs(g) * dt

    def predict(self, action: str) -> np.ndarray:
        try:
            alpha = self.alphas[action]
        except KeyError:
            raise ConfigError(f"no calibrated alpha for action {action!r}; calibrated: {sorted(self.alphas)}",
                              where="KWearIndex.predict") from None
        return predict(self._v, alpha)

    def start_action(self, action: str) -> None:
        self._action = action
        self._integral[:] = 0.0

    def finish_action(self) -> np.ndarray | None:
        """End the current action; returns its measured alpha (5,) and, if ``online_weight`` > 0, folds it
        into the action's alpha. None if no action was started."""
        if self._action is None:
            return None
        measured = np.exp(-self._integral / self.params.C)
        if self.online_weight > 0 and self._action in self.alphas:
            self.alphas[self._action] = online_alpha(self.alphas[self._action], measured, self.online_weight)
        self._action = None
        return measured

    def _reset(self) -> None:
        self._action = None
        self._integral[:] = 0.0


class StaticRulaIndex(RiskIndex):
    """The paper's static RULA baseline: a constant score G(a_k) per action, whatever the history.

    g_actions: action -> G(a_k) (e.g. ``Calibration.rula_scores``). :meth:`predict` returns
    ``[G(a_k) / g_max]``, so the cost model's V_th = G_th / g_max (default 0.8 -> G_th = 7.2 with the
    paper's G_max = 9). ``value`` is the latest valid part scores G (5,), for display.
    """

    channels = ("rula",)

    def __init__(self, g_actions: Mapping[str, float], g_max: float = 9.0) -> None:
        super().__init__()
        if not (math.isfinite(g_max) and g_max > 0):
            raise ConfigError(f"g_max must be > 0, got {g_max}", where="StaticRulaIndex.g_max")
        bad = {a: g for a, g in g_actions.items() if not (math.isfinite(g) and g >= 0)}
        if bad:
            raise ConfigError(f"RULA scores must be finite and >= 0, got {bad}", where="StaticRulaIndex")
        self.g_actions = dict(g_actions)
        self.g_max = float(g_max)
        self.scale = self.g_max  # predictions are G / G_max

    @classmethod
    def from_worker(cls, worker, g_max: float = 9.0) -> StaticRulaIndex:
        """From :class:`~ergosim.ergonomics.param_store.WorkerParams` (its ``rula_scores``)."""
        return cls(worker.rula_scores, g_max)

    def _advance(self, g: np.ndarray, dt: float, resting: bool) -> None:
        if not resting:
            self._v[:] = g

    def predict(self, action: str) -> np.ndarray:
        try:
            return np.array([self.g_actions[action] / self.g_max])
        except KeyError:
            raise ConfigError(f"no RULA score for action {action!r}; known: {sorted(self.g_actions)}",
                              where="StaticRulaIndex.predict") from None
