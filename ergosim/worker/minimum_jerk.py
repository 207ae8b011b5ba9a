"""Minimum-jerk transitions between key poses.

A point-to-point human reach follows the minimum-jerk profile (Flash & Hogan 1985, J Neurosci 5:1688):
``s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5`` for normalised time tau in [0, 1], zero velocity and
acceleration at both ends. Segment durations come from MTM-1 (:mod:`ergosim.worker.action_timing`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["min_jerk", "min_jerk_velocity", "interpolate_keyframes"]


def min_jerk(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk progress s(tau) in [0, 1] for normalised time tau (clipped to [0, 1]); any shape."""
    t = np.clip(tau, 0.0, 1.0)
    return t * t * t * (10.0 + t * (-15.0 + 6.0 * t))


def min_jerk_velocity(tau: np.ndarray) -> np.ndarray:
    """ds/dtau of the minimum-jerk profile (multiply by 1/T for a rate in 1/s); peak 1.875 at tau = 0.5."""
    t = np.clip(tau, 0.0, 1.0)
    return 30.0 * t * t * (1.0 - t) ** 2


def interpolate_keyframes(key_times: np.ndarray, key_values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Minimum-jerk interpolation through keyframes, vectorised over samples.

    key_times: (k,) increasing [s]; key_values: (k, m); t: (n,) sample times [s]. Each segment between two
    keyframes is a minimum-jerk transition (equal keyframes give a dwell). Returns (n, m); samples outside
    [key_times[0], key_times[-1]] hold the end values.
    """
    key_times = np.asarray(key_times, dtype=float)
    key_values = np.asarray(key_values, dtype=float)
    seg = np.clip(np.searchsorted(key_times, t, side="right") - 1, 0, len(key_times) - 2)
    t0, t1 = key_times[seg], key_times[seg + 1]
    span = np.where(t1 > t0, t1 - t0, 1.0)
    s = min_jerk((t - t0) / span)[:, None]
    return key_values[seg] + (key_values[seg + 1] - key_values[seg]) * s
