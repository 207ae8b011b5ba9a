"""Calibration of the KWear prediction model (paper §5): alpha_{k,i} per action and joint, adaptive eta.

Each execution of action a_k starts at zero wear, so its coefficient is alpha_{k,i,l} = exp(-int G_i/C)
= 1 - V_{i,l}(t_end) (eq. 4 and 9). The calibrated alpha_{k,i} is the mean over eta executions. eta starts
at eta_0 >= 2; while some prediction error |V_hat_{i,eta} - V_{i,l}| (V_hat from the mean alpha, eq. 9,
from zero wear) is not below V_des for every joint i and execution l, one more execution is recorded,
up to eta_max. The caller supplies executions through ``execute(l)``: the simulated worker or recordings.
The online weighted-average update of alpha after each executed action is :func:`online_alpha`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.kwear import KWearParams, alpha_of
from ergosim.ergonomics.rula import part_scores, rula
from ergosim.ergonomics.rula_action import action_grand_score
from ergosim.errors import ConfigError, RecordingError
from ergosim.posture import KWEAR_JOINTS, array_to_posture

__all__ = [
    "Execution",
    "ActionCalibration",
    "Calibration",
    "execution_from_angles",
    "calibrate_action",
    "calibrate",
    "online_alpha",
]


class Execution(NamedTuple):
    """One recorded execution of an action, started at zero wear.

    g: (n, m) part scores G_i of the index's posture feature, e.g. (n, 5) RULA part scores in KWEAR_JOINTS
    order or (n, 6) REBA part scores in REBA_JOINTS order (NaN rows = dropouts, contributing no wear);
    dt: tick length [s], scalar or (n,); grand: optional (n,) whole-body scores (RULA grand, REBA score),
    for a static baseline.
    """

    g: np.ndarray
    dt: float | np.ndarray
    grand: np.ndarray | None = None


def execution_from_angles(angles, dt: float | np.ndarray, **rula_kwargs) -> Execution:
    """Score a recorded execution: angles (n, 14) in ANGLE_NAMES order or a posture of (n,) arrays [deg]."""
    posture = angles if isinstance(angles, Mapping) else array_to_posture(np.atleast_2d(angles))
    res = rula(posture, **rula_kwargs)
    return Execution(part_scores(res).reshape(-1, len(KWEAR_JOINTS)), dt, np.atleast_1d(res.grand))


@dataclass(frozen=True)
class ActionCalibration:
    """Calibration of one action. Arrays are (m,) per joint or (eta, m) per execution and joint.

    ``alpha``: mean coefficient (eq. 9); ``alphas``: per execution; ``errors``: |V_hat - V_l| of each
    execution with the final mean; ``converged``: every error < ``v_des`` (else eta_max was reached);
    ``rula_grand``: G(a_k) under its rule ``G_RULE`` (:mod:`ergosim.ergonomics.rula_action`): the RULA grand
    score for the static RULA baseline, the REBA score when the executions carry REBA's (NaN if no
    whole-body scores were given);
    ``duration``: mean execution time [s]; ``dropouts``: non-finite rows over all executions.
    """

    action: str
    alpha: np.ndarray
    eta: int
    alphas: np.ndarray
    errors: np.ndarray
    converged: bool
    v_des: float
    rula_grand: float
    duration: float
    dropouts: int

    @property
    def max_error(self) -> np.ndarray:
        """(m,) worst prediction error per joint over the eta executions."""
        return self.errors.max(axis=0)


@dataclass(frozen=True)
class Calibration:
    """Calibration of a set of actions for one worker with the given KWear parameters."""

    params: KWearParams
    actions: Mapping[str, ActionCalibration] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "actions", MappingProxyType(dict(self.actions)))

    @property
    def alphas(self) -> dict[str, np.ndarray]:
        return {a: c.alpha for a, c in self.actions.items()}

    @property
    def rula_scores(self) -> dict[str, float]:
        """action -> G(a_k), the whole-body score held longest (RULA's grand score on RULA part scores)."""
        return {a: c.rula_grand for a, c in self.actions.items()}

    @property
    def grand_scores(self) -> dict[str, float]:
        """action -> G(a_k) of the calibrated feature: RULA's grand score, or the REBA score."""
        return self.rula_scores

    @property
    def eta(self) -> dict[str, int]:
        return {a: c.eta for a, c in self.actions.items()}


def _check(ex, action: str, run: int, joints: int | None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    where = f"calibration of {action!r}, execution {run}"
    try:
        g, dt, *rest = ex
    except (TypeError, ValueError):
        raise RecordingError("execute(l) must return (g (n, m), dt[, grand (n,)])", where=where) from None
    g = np.asarray(g, dtype=float)
    if g.ndim != 2 or g.shape[1] < 1 or len(g) == 0 or (joints is not None and g.shape[1] != joints):
        want = f"(n >= 1, {joints})" if joints is not None else "(n >= 1, m >= 1)"
        raise RecordingError(f"G must have shape {want}, got {g.shape}", where=where)
    dts = np.broadcast_to(np.asarray(dt, dtype=float), (len(g),))
    if not np.all(np.isfinite(dts) & (dts > 0)):
        raise RecordingError(f"dt must be finite and > 0 s, got {dt!r}", where=where)
    if not np.isfinite(g).all(axis=1).any():
        raise RecordingError("every frame is a dropout: nothing to calibrate from", where=where)
    grand = None if not rest or rest[0] is None else np.asarray(rest[0], dtype=float).reshape(-1)
    return g, dts, grand


def calibrate_action(execute: Callable[[int], Execution | tuple], params: KWearParams = KWearParams(), *,
                     v_des: float = 1e-3, eta0: int = 2, eta_max: int = 10,
                     action: str = "", joints: int | None = None) -> ActionCalibration:
    """Adaptive-eta calibration of one action (paper §5).

    execute(l) -> (g (n, m), dt[, grand (n,)]) records execution l = 0, 1, ... from zero wear; every
    execution has the same m joints, ``joints`` if given (5 for RULA's KWear, 6 for REBA's).
    v_des: target maximum prediction error Ṽ_des; eta0 >= 2 initial executions; eta_max the cap.
    G(a_k) is :func:`~ergosim.ergonomics.rula_action.action_grand_score` of the executions' grand scores.
    """
    if not (isinstance(eta0, int) and eta0 >= 2 and isinstance(eta_max, int) and eta_max >= eta0):
        raise ConfigError(f"need integers eta0 >= 2 and eta_max >= eta0, got eta0={eta0}, eta_max={eta_max}",
                          where="calibration")
    if not v_des > 0:
        raise ConfigError(f"v_des must be > 0, got {v_des}", where="calibration")
    alphas, grands, durations, dropouts = [], [], [], 0
    while True:
        run = len(alphas)
        g, dts, grand = _check(execute(run), action, run, len(alphas[0]) if alphas else joints)
        alphas.append(alpha_of(g, dts, params))
        durations.append(float(dts.sum()))
        dropouts += int((~np.isfinite(g).all(axis=1)).sum())
        if grand is not None:
            grands.append(grand)
        if len(alphas) < eta0:
            continue
        a = np.array(alphas)
        mean = a.mean(axis=0)
        # V_hat - V_l from zero wear: (1 - mean) - (1 - alpha_l)
        errors = np.abs(a - mean)
        converged = bool(np.all(errors < v_des))
        if converged or len(a) >= eta_max:
            break
    g_rula = action_grand_score(grands, dt=float(np.median(dts)))
    return ActionCalibration(action, mean, len(a), a, errors, converged, float(v_des), g_rula,
                             float(np.mean(durations)), dropouts)


def calibrate(actions: Iterable[str], execute: Callable[[str, int], Execution | tuple],
              params: KWearParams = KWearParams(), **kwargs) -> Calibration:
    """Calibrate every action; ``execute(action, l)`` records execution l of ``action`` from zero wear.
    Keyword arguments go to :func:`calibrate_action`."""
    out = {}
    for a in actions:
        out[a] = calibrate_action(lambda run, a=a: execute(a, run), params, action=a, **kwargs)
    return Calibration(params, out)


def online_alpha(alpha, alpha_last, weight: float) -> np.ndarray:
    """Weighted-average update after an executed action (paper §5, last paragraph):
    (1 - weight) alpha + weight alpha_last; weight in [0, 1], 0 keeps the calibrated alpha."""
    if not 0.0 <= weight <= 1.0:
        raise ConfigError(f"online alpha weight must be in [0, 1], got {weight}", where="online_alpha")
    return (1.0 - weight) * np.asarray(alpha, dtype=float) + weight * np.asarray(alpha_last, dtype=float)
