"""Time scaling of a geometric path: where along it the robot is at every physics step.

:func:`trapezoid` is the classic single-speed profile. :func:`speed_profile` is the fastest rest-to-rest
motion along a path cut into pieces, each with its own speed cap and acceleration limit: the speed rises
at most as fast as the acceleration allows, never exceeds a piece's cap, and brakes in time for the next,
slower piece (the forward-backward pass of time-optimal path parameterisation, here with piecewise-constant
caps, so it has a closed form per pass). A path whose last few centimetres are contact-critical thus runs
at the transit speed, brakes to the contact speed just before the contact zone and crosses it slowly,
without stopping in between.
"""

from __future__ import annotations

import numpy as np

__all__ = ["trapezoid", "speed_profile"]

_SUBSTEPS_PER_RAMP = 16
"""Sub-steps into which the distance needed to reach a piece's cap is cut (the passes' resolution)."""
_MIN_SUBSTEPS = 32
"""Sub-steps of any piece at least (a triangular profile peaks between two of them)."""
_MAX_SUBSTEPS = 400


def trapezoid(distance: float, speed: float, accel: float, dt: float) -> np.ndarray:
    """Normalised path parameter s(t) in [0, 1] at t = dt, 2 dt, ... of a trapezoidal (or triangular)
    speed profile over ``distance`` with peak ``speed`` and acceleration ``accel``; ends exactly at 1."""
    if distance <= 0:
        return np.array([1.0])
    t_acc = speed / accel
    if accel * t_acc**2 >= distance:  # triangular
        t_acc = np.sqrt(distance / accel)
        speed = accel * t_acc
    t_total = 2 * t_acc + (distance - accel * t_acc**2) / speed
    t = np.arange(1, int(np.ceil(t_total / dt)) + 1) * dt
    t = np.minimum(t, t_total)
    s = np.where(t < t_acc, 0.5 * accel * t**2,
                 np.where(t < t_total - t_acc, 0.5 * accel * t_acc**2 + speed * (t - t_acc),
                          distance - 0.5 * accel * (t_total - t) ** 2))
    return np.clip(s / distance, 0.0, 1.0)


def speed_profile(steps: np.ndarray, caps: np.ndarray, accels: np.ndarray, dt: float) -> np.ndarray:
    """Path position at t = dt, 2 dt, ... of the fastest rest-to-rest motion along consecutive pieces of
    length ``steps`` (k,) whose speed may not exceed ``caps`` (k,) and whose acceleration and braking may
    not exceed ``accels`` (k,) while on that piece. Lengths in any unit u (metres, or a normalised path
    parameter), caps in u/s, accelerations in u/s^2, ``dt`` [s]. Ends exactly at ``steps.sum()``."""
    steps = np.asarray(steps, dtype=float)
    caps = np.asarray(caps, dtype=float)
    accels = np.asarray(accels, dtype=float)
    total = float(steps.sum())
    if total <= 0:
        return np.array([total])
    ramp = caps**2 / (2 * accels)
    m = np.clip(np.ceil(_SUBSTEPS_PER_RAMP * steps / np.maximum(ramp, 1e-300)), _MIN_SUBSTEPS,
                _MAX_SUBSTEPS).astype(int)
    h = np.repeat(steps / m, m)  # (n,) sub-step lengths
    a = np.repeat(accels, m)
    cap = np.repeat(caps, m)
    n = len(h)
    # squared speed at the n + 1 nodes: capped by both neighbouring sub-steps, zero at the ends
    w_max = np.empty(n + 1)
    w_max[0] = w_max[n] = 0.0
    w_max[1:n] = np.minimum(cap[:-1], cap[1:]) ** 2
    gain = np.concatenate([[0.0], np.cumsum(2 * a * h)])  # w may grow by 2 a h per sub-step
    # forward: w_j = min_{i<=j} (w_max_i + gain_j - gain_i); backward: the same from the far end
    w = gain + np.minimum.accumulate(w_max - gain)
    w = np.minimum(w, (np.minimum.accumulate((w + gain)[::-1]))[::-1] - gain)
    v = np.sqrt(np.maximum(w, 0.0))
    # constant acceleration within a sub-step: exact time and position
    dt_sub = 2 * h / (v[:-1] + v[1:])
    t_node = np.concatenate([[0.0], np.cumsum(dt_sub)])
    x_node = np.concatenate([[0.0], np.cumsum(h)])
    acc = (v[1:] ** 2 - v[:-1] ** 2) / (2 * h)
    t = np.minimum(np.arange(1, int(np.ceil(t_node[-1] / dt - 1e-9)) + 1) * dt, t_node[-1])
    j = np.clip(np.searchsorted(t_node, t, side="right") - 1, 0, n - 1)
    tau = t - t_node[j]
    x = np.minimum(x_node[j] + v[j] * tau + 0.5 * acc[j] * tau**2, x_node[j + 1])
    x[-1] = total
    return x
