"""Risk indices: the extension point that decouples the framework from KWear (paper §5: the framework "is
not coupled with any specific metric").

The contract. A :class:`RiskIndex` declares

- the **posture feature** it reads (``features``, one of :data:`~ergosim.ergonomics.features.FEATURES`:
  ``rula`` the RULA part scores (5,), ``reba`` the REBA part scores with the legs (6,), ``angles`` the 14
  canonical joint angles [deg]); the twin computes that feature for every measured frame and passes its
  row to :meth:`~RiskIndex.update` once per ergonomics tick;
- its **per-tick state**, ``value`` (m,) named by ``joints`` (the feature's columns);
- its **prediction**, :meth:`~RiskIndex.predict` (p,) per candidate action, named by ``channels``, which
  the cost model (eq. 10-11) turns into a hyper-arc cost;
- its **calibration**: what it is built from, a :class:`~ergosim.ergonomics.calibration.Calibration` of
  the same feature (α per action for KWear, the whole-body score G(a_k) per action for a static index).

Implementations: :class:`KWearIndex` (eq. 3-9 with calibrated alphas, on RULA or REBA part scores),
:class:`StaticRulaIndex` (the paper's static RULA baseline, a constant G(a_k) per action) and
:class:`StaticRebaIndex` (the same rule on the REBA score).

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
from ergosim.ergonomics.reba import REBA_JOINTS
from ergosim.errors import ConfigError
from ergosim.posture import KWEAR_JOINTS

__all__ = ["RiskIndex", "KWearIndex", "StaticRulaIndex", "StaticRebaIndex", "REBA_G_MAX", "REBA_G_HIGH"]

REBA_G_MAX = 15.0
"""The largest REBA score (Table C's 12 plus an activity score of 3)."""
REBA_G_HIGH = 8.0
"""The first REBA score of the "high risk" band (8-10, action level 3: action necessary soon)."""


class RiskIndex(ABC):
    """Per-worker ergonomic risk state, advanced per tick and predicted per candidate action.

    ``features``: the posture feature read (module docstring); ``value``: (m,) current value per joint,
    named by ``joints``. :meth:`predict` returns the (p,) predicted risk the cost model sums (eq. 11), with
    ``channels`` naming its p entries; the cost threshold V_th is compared with these numbers. Subclasses
    implement :meth:`_advance`, :meth:`predict` and :meth:`_reset`; the base class handles dropouts and
    counting.
    """

    features: str = "rula"
    joints: tuple[str, ...] = KWEAR_JOINTS
    channels: tuple[str, ...] = KWEAR_JOINTS
    scale: float = 1.0
    """A predicted value × ``scale`` is the index's own unit, for display (the static RULA index: G_max)."""

    def __init__(self, joints: tuple[str, ...] | None = None) -> None:
        if joints is not None:
            self.joints = tuple(joints)
        self._v = np.zeros(len(self.joints))
        self.ticks = 0
        self.dropouts = 0

    @property
    def value(self) -> np.ndarray:
        """(m,) current value per joint (a read-only view)."""
        v = self._v.view()
        v.flags.writeable = False
        return v

    def update(self, g, dt: float, resting: bool = False) -> np.ndarray:
        """Advance one tick of ``dt`` [s] with the feature's row G (m,); ``resting`` True while the worker is
        not executing an action. A non-finite G row is a dropout: counted, and while acting V holds."""
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
        """Back to zero (or ``v0`` (m,)) state; counters restart."""
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


def _alpha_table(alphas: Mapping[str, object], m: int) -> dict[str, np.ndarray]:
    out = {}
    for a, x in alphas.items():
        arr = np.array(x, dtype=float)
        if arr.shape != (m,) or not np.all((arr > 0) & (arr <= 1)):
            raise ConfigError(f"alpha of action {a!r} must be {m} values in (0, 1], got {x!r}",
                              where=f"KWearIndex.alphas[{a!r}]")
        out[a] = arr
    return out


class KWearIndex(RiskIndex):
    """KWear per joint (eq. 3-5) and its prediction V_hat = 1 - alpha (1 - V) (eq. 9).

    alphas: action -> (m,) calibrated alpha (:mod:`ergosim.ergonomics.calibration`), calibrated on the
    same feature. online_weight: weight of the latest execution in the online alpha average (paper §5); 0
    (default, as in the paper's experiments) keeps the calibrated alphas. The executed action's alpha is
    exp(-int |G| dt / C) over its acting ticks (independent of V at its start, eq. 4).
    features / joints: the posture feature and its joints: ``rula`` with KWEAR_JOINTS (the paper's), or
    ``reba`` with REBA_JOINTS (the REBA-driven variant, the same eq. 3-9 on REBA part scores).
    """

    def __init__(self, params: KWearParams, alphas: Mapping[str, object], online_weight: float = 0.0,
                 v0=None, *, features: str = "rula", joints: tuple[str, ...] | None = None) -> None:
        super().__init__(joints)
        self.features = features
        self.channels = self.joints
        if not 0.0 <= online_weight <= 1.0:
            raise ConfigError(f"online_weight must be in [0, 1], got {online_weight}", where="KWearIndex")
        self.params = params
        self.alphas = _alpha_table(alphas, len(self.joints))
        self.online_weight = float(online_weight)
        self._action: str | None = None
        self._integral = np.zeros(len(self.joints))
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
        """End the current action; returns its measured alpha (m,) and, if ``online_weight`` > 0, folds it
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
    paper's G_max = 9). ``value`` is the latest valid part scores G (m,), for display.
    """

    channels = ("rula",)
    score_name = "RULA"

    def __init__(self, g_actions: Mapping[str, float], g_max: float = 9.0) -> None:
        super().__init__()
        if not (math.isfinite(g_max) and g_max > 0):
            raise ConfigError(f"g_max must be > 0, got {g_max}", where=f"{type(self).__name__}.g_max")
        bad = {a: g for a, g in g_actions.items() if not (math.isfinite(g) and g >= 0)}
        if bad:
            raise ConfigError(f"{self.score_name} scores must be finite and >= 0, got {bad}",
                              where=type(self).__name__)
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
            where = f"{type(self).__name__}.predict"
            raise ConfigError(f"no {self.score_name} score for action {action!r}; "
                              f"known: {sorted(self.g_actions)}", where=where) from None


class StaticRebaIndex(StaticRulaIndex):
    """A static REBA baseline: the rule of :class:`StaticRulaIndex` on the REBA score G(a_k) of each action
    (the score held longest, 1..15). g_max defaults to :data:`REBA_G_MAX`; ``value`` is the latest valid
    REBA part scores (6,), REBA_JOINTS order."""

    features = "reba"
    channels = ("reba",)
    score_name = "REBA"

    def __init__(self, g_actions: Mapping[str, float], g_max: float = REBA_G_MAX) -> None:
        self.joints = REBA_JOINTS
        super().__init__(g_actions, g_max)
