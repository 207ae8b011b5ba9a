"""Time scaling of a geometric path: where along it the robot is at every physics step.

:func:`trapezoid` is the classic single-speed profile. :func:`speed_profile` is the fastest rest-to-rest
motion along a path cut into pieces, each with its own speed cap and acceleration limit: the speed rises
at most as fast as the acceleration allows, never exceeds a piece's cap, and brakes in time for the next,
slower piece. It is the forward-backward pass of time-optimal path parameterisation; with piecewise-constant
caps and accelerations it is exact at the pieces' ends, and each piece is a trapezoid between them. A path
whose last few centimetres are contact-critical thus runs at the transit speed, brakes to the contact
speed just before the contact zone and crosses it slowly, without stopping in between.
"""

from __future__ import annotations

import numpy as np

__all__ = ["trapezoid", "speed_profile"]


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
    parameter), caps in u/s, accelerations in u/s^2, ``dt`` [s]. Ends exactly at ``steps.sum()``.

    The speeds at the pieces' ends come from a forward and a backward pass (the speed may rise by at most
    sqrt(2 a L) over a piece and must be low enough to brake for the next); within a piece the motion is
    then a trapezoid between its end speeds, so positions are exact at every sample."""
    steps = np.asarray(steps, dtype=float)
    caps = np.asarray(caps, dtype=float)
    a = np.asarray(accels, dtype=float)
    total = float(steps.sum())
    if total <= 0:
        return np.array([total])
    k = len(steps)
    # squared speed at the k + 1 piece ends: capped by both neighbouring pieces, zero at the two ends
    w_max = np.empty(k + 1)
    w_max[0] = w_max[k] = 0.0
    w_max[1:k] = np.minimum(caps[:-1], caps[1:]) ** 2
    gain = np.concatenate([[0.0], np.cumsum(2 * a * steps)])  # w may grow by 2 a L over a piece
    # forward: w_j = min_{i<=j} (w_max_i + gain_j - gain_i); backward: the same from the far end
    w = gain + np.minimum.accumulate(w_max - gain)
    w = np.maximum(np.minimum(w, (np.minimum.accumulate((w + gain)[::-1]))[::-1] - gain), 0.0)
    v0, v1 = np.sqrt(w[:-1]), np.sqrt(w[1:])
    # per piece: accelerate from v0 to the peak, cruise, brake to v1
    peak = np.minimum(caps, np.sqrt((w[:-1] + w[1:] + 2 * a * steps) / 2))
    peak = np.maximum(peak, np.maximum(v0, v1))
    t_acc = (peak - v0) / a
    t_dec = (peak - v1) / a
    x_acc = (peak**2 - w[:-1]) / (2 * a)
    x_dec = (peak**2 - w[1:]) / (2 * a)
    x_cru = np.maximum(steps - x_acc - x_dec, 0.0)
    t_cru = np.where(peak > 0, x_cru / np.maximum(peak, 1e-300), 0.0)
    t_piece = t_acc + t_cru + t_dec
    t_start = np.concatenate([[0.0], np.cumsum(t_piece)])
    x_start = np.concatenate([[0.0], np.cumsum(steps)])
    t = np.minimum(np.arange(1, int(np.ceil(t_start[-1] / dt - 1e-9)) + 1) * dt, t_start[-1])
    i = np.clip(np.searchsorted(t_start, t, side="right") - 1, 0, k - 1)
    tau = t - t_start[i]
    ta, tc = t_acc[i], t_cru[i]
    in_acc = tau < ta
    in_cru = ~in_acc & (tau < ta + tc)
    td = np.maximum(tau - ta - tc, 0.0)
    x = np.where(in_acc, v0[i] * tau + 0.5 * a[i] * tau**2,
                 np.where(in_cru, x_acc[i] + peak[i] * (tau - ta),
                          x_acc[i] + x_cru[i] + peak[i] * td - 0.5 * a[i] * td**2))
    x = np.minimum(x_start[i] + x, x_start[i + 1])
    x[-1] = total
    return x
