"""Kinematic Wear (KWear), paper eq. 3-9: an RC model of joint wear driven by the RULA part scores.

For each monitored joint i (:data:`ergosim.posture.KWEAR_JOINTS`), with G_i its RULA part score:

- wear (eq. 3-4):     dV/dt = (1 - V)|G|/C   ->  V(t + dt) = 1 - (1 - V(t)) exp(-|G| dt / C)
- recovery (eq. 5):   dV/dt = -V r/C         ->  V(t + dt) = V(t) exp(-r dt / C)

:func:`kwear_step` applies the exact solution over one tick with G held constant (no Euler error), so
V stays in [0, 1) for any tick length. C and r follow from T_max, V_max and G_avg (eq. 6-7).
The prediction after an action with coefficient alpha = exp(-int G dt / C) is eq. 9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ergosim.errors import ConfigError

__all__ = ["KWearParams", "V_CEIL", "kwear_step", "kwear_trajectory", "alpha_of", "predict"]

V_CEIL = float(np.nextafter(1.0, 0.0))
"""Largest float below 1. After ~37 wear time constants 1 - V underflows in float64; V is capped here so
the invariant V < 1 of eq. 4 also holds in floating point."""


@dataclass(frozen=True)
class KWearParams:
    """KWear constants (paper eq. 6-7): ``t_max`` [s] time to reach ``v_max`` from 0 at RULA ``g_avg``.

    ``C`` is the endurance capacity [score s] and ``r`` the recovery rate [score]; the recovery time
    constant is C/r [s]. Paper defaults give C = 145.107 and r = 2.9958. Overrides per subject are allowed.
    """

    t_max: float = 240.0
    v_max: float = 0.993
    g_avg: float = 3.0

    def __post_init__(self) -> None:
        for name in ("t_max", "v_max", "g_avg"):
            if not isinstance(getattr(self, name), (int, float)) or not math.isfinite(getattr(self, name)):
                raise ConfigError(f"KWear {name} must be a finite number, got {getattr(self, name)!r}",
                                  where=f"KWearParams.{name}")
        if self.t_max <= 0 or self.g_avg <= 0:
            raise ConfigError(f"KWear t_max and g_avg must be > 0, got t_max={self.t_max}, "
                              f"g_avg={self.g_avg}", where="KWearParams")
        if not 0.5 < self.v_max < 1.0:
            # r > 0 (eq. 7) needs ln((1 - V_max)/V_max) < 0, i.e. V_max > 0.5; V_max < 1 for eq. 6.
            raise ConfigError(f"KWear v_max must be in (0.5, 1), got {self.v_max}", where="KWearParams.v_max")

    @cached_property
    def C(self) -> float:  # noqa: N802 - the paper's symbol
        """Endurance capacity, eq. 6: C = -G_avg T_max / ln(1 - V_max)."""
        return -self.g_avg * self.t_max / math.log(1.0 - self.v_max)

    @cached_property
    def r(self) -> float:
        """Recovery rate, eq. 7: r = -(C / T_max) ln((1 - V_max) / V_max)."""
        return -(self.C / self.t_max) * math.log((1.0 - self.v_max) / self.v_max)


def kwear_step(v, g, dt: float, params: KWearParams, resting=False,
               out: np.ndarray | None = None) -> np.ndarray:
    """One exact KWear tick (eq. 4 wear, eq. 5 recovery) with G held constant over ``dt``.

    v: (m,) KWear in [0, 1); g: (m,) RULA part scores (sign ignored, eq. 3 uses |G|); dt [s] >= 0;
    resting: bool or (m,) bool, True -> recovery (G unused). A non-finite G_i (dropout) leaves V_i
    unchanged. Returns the new (m,) V (written into ``out`` if given; ``out`` may be ``v``).
    """
    v = np.asarray(v, dtype=float)
    if not dt >= 0:  # also rejects NaN, which would poison V
        raise ValueError(f"dt must be >= 0 s, got {dt}")
    k = dt / params.C
    if resting is True or (resting is not False and np.ndim(resting) == 0 and resting):
        return np.multiply(v, math.exp(-params.r * k), out=out)
    x = np.abs(np.asarray(g, dtype=float))
    x *= -k
    finite = bool(np.isfinite(x).all())
    bad = None if finite else ~np.isfinite(x)  # dropouts: rare, so the mask is built only when needed
    np.expm1(x, out=x)
    # V + (1 - V)(1 - e^-x) written with expm1: exact at x = 0 and accurate for the short ticks used.
    res = v - (1.0 - v) * x
    np.minimum(res, V_CEIL, out=res)
    if bad is not None:
        res = np.where(bad, v, res)
    if resting is not False and np.ndim(resting) > 0:
        res = np.where(np.asarray(resting, dtype=bool), v * math.exp(-params.r * k), res)
    if out is None:
        return res
    out[...] = res
    return out


def kwear_trajectory(v0, g, dt, params: KWearParams, resting=False) -> np.ndarray:
    """KWear after each of n ticks: v0 (m,), g (n, m) scores, dt scalar or (n,) [s], resting bool or (n,)
    or (n, m). Returns (n, m). Exact (eq. 4-5); non-finite G rows hold V, as in :func:`kwear_step`.

    The same floating-point operations as n calls of :func:`kwear_step`, so the same bits: the exponentials
    for all ticks at once, then the recursion V_k(V_{k-1}) on Python floats.
    """
    g = np.atleast_2d(np.asarray(g, dtype=float))
    n, m = g.shape
    dts = np.broadcast_to(np.asarray(dt, dtype=float), (n,))
    rest = np.broadcast_to(np.asarray(resting, dtype=bool), (n,) if np.ndim(resting) <= 1 else (n, m))
    v = [float(x) for x in np.broadcast_to(np.asarray(v0, dtype=float), (m,))]
    if not np.all(dts >= 0):
        raise ValueError(f"dt must be >= 0 s, got {float(dts[np.flatnonzero(~(dts >= 0))[0]])}")
    k = np.array([float(d) / params.C for d in dts.tolist()])
    x = np.abs(g)
    x *= -k[:, None]
    # per tick and joint: 0 wear (eq. 4), 1 hold (a dropout while acting), 2 recovery (eq. 5)
    kind = np.where(np.broadcast_to(rest if rest.ndim == 2 else rest[:, None], (n, m)), 2,
                    np.where(np.isfinite(x), 0, 1))
    np.expm1(x, out=x)
    decay = {d: math.exp(-params.r * d) for d in set(k.tolist())}
    factors = [decay[d] for d in k.tolist()]
    out = np.empty((n, m))
    for i in range(m):
        vi, column = v[i], []
        for xt, kt, ft in zip(x[:, i].tolist(), kind[:, i].tolist(), factors, strict=True):
            if kt == 0:
                vi = vi - (1.0 - vi) * xt
                if vi > V_CEIL:
                    vi = V_CEIL
            elif kt == 2:
                vi = vi * ft
            column.append(vi)
        out[:, i] = column
    return out


def alpha_of(g, dt, params: KWearParams) -> np.ndarray:
    """Prediction coefficient of an execution (eq. 9): alpha_i = exp(-sum_t |G_i(t)| dt / C).

    g: (n, m) part scores over the execution; dt: scalar or (n,) [s]. Non-finite rows (dropouts)
    contribute no wear, matching :func:`kwear_step`. Equals 1 - V_end for an execution started at V = 0.
    """
    g = np.atleast_2d(np.abs(np.asarray(g, dtype=float)))
    dts = np.broadcast_to(np.asarray(dt, dtype=float), (g.shape[0],))
    integral = np.where(np.isfinite(g), g, 0.0).T @ dts
    return np.exp(-integral / params.C)


def predict(v, alpha) -> np.ndarray:
    """Predicted KWear after an action, eq. 9: V_hat = 1 - alpha (1 - V). Broadcasts, e.g. v (m,) with
    alpha (n_actions, m) -> (n_actions, m)."""
    return 1.0 - np.asarray(alpha, dtype=float) * (1.0 - np.asarray(v, dtype=float))
