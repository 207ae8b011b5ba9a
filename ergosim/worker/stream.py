"""Synthetic motion capture: the worker's true motion, measured like an inertial (Xsens-like) suit.

Each joint angle is measured with a slowly drifting bias (an Ornstein-Uhlenbeck process: IMU heading and
soft-tissue drift, a few degrees over minutes) plus white noise; optional dropouts blank whole frames to NaN
in bursts, as when the suit loses its radio link. The bias state persists across actions, so one stream is
one continuous recording. The *true* angles (not the measurement) drive the human in the scene, so the hand
that holds a part moves it where the worker really is.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ergosim.human.mocap import MocapHuman
from ergosim.human.model import HumanModel, body_qpos
from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.subjects import Subject

__all__ = ["MocapFrames", "MocapStream", "MotionPlayback"]


@dataclass(frozen=True)
class MocapFrames:
    """Measured frames. ``t``: (n,) [s]; ``angles``: (n, 22) [deg], NaN rows are dropouts; ``valid``: (n,)."""

    t: np.ndarray
    angles: np.ndarray
    valid: np.ndarray

    @property
    def dropouts(self) -> int:
        return int((~self.valid).sum())


class MocapStream:
    """Measures trajectories of one subject at ``rate`` [Hz] (default 60 Hz, Xsens-like).

    ``dropout_rate``: probability per frame that a dropout burst starts; bursts last a geometric number of
    frames with mean ``dropout_frames``. ``bias_tau`` [s]: correlation time of the drifting bias.
    """

    def __init__(self, subject: Subject, rng: np.random.Generator, rate: float = 60.0,
                 dropout_rate: float = 0.0, dropout_frames: float = 3.0, bias_tau: float = 30.0,
                 noise: bool | float = True) -> None:
        self.subject = subject
        self.rng = rng
        self.rate = float(rate)
        self.dropout_rate = float(dropout_rate)
        self.dropout_frames = float(dropout_frames)
        self.bias_tau = float(bias_tau)
        # noise: True/1.0 the subject's sensor noise, False/0.0 none, a float scales bias and white noise
        self.noise = noise
        self.noise_scale = float(noise)
        n = len(HUMAN_JOINTS)
        self.bias = (self.noise_scale * rng.normal(0.0, subject.bias_deg, n) if self.noise_scale > 0
                     else np.zeros(n))
        self.dropouts = 0
        self.frames = 0
        self._in_dropout = 0

    def measure(self, angles: np.ndarray, t0: float = 0.0) -> MocapFrames:
        """Measure (n, 22) true angles [deg] sampled at ``rate``; frames are time-stamped from ``t0`` [s]."""
        angles = np.asarray(angles, dtype=float)
        n = len(angles)
        t = t0 + np.arange(n) / self.rate
        out = angles.copy()
        if self.noise_scale > 0:
            # exact discretisation of the OU bias: b_k+1 = a b_k + sqrt(1 - a^2) sigma w_k
            a = np.exp(-1.0 / (self.rate * self.bias_tau))
            sigma = self.noise_scale * self.subject.bias_deg
            w = self.rng.normal(0.0, sigma * np.sqrt(1.0 - a * a), angles.shape)
            bias = _ou_bias(w, a, self.bias)
            if n:
                self.bias = bias[-1].copy()
            out += bias + self.rng.normal(0.0, self.noise_scale * self.subject.noise_deg, angles.shape)
        valid = np.ones(n, dtype=bool)
        if self.dropout_rate > 0.0:
            starts = self.rng.random(n) < self.dropout_rate
            lengths = self.rng.geometric(1.0 / self.dropout_frames, n)
            left = self._in_dropout
            for k in range(n):
                if left == 0 and starts[k]:
                    left = lengths[k]
                if left > 0:
                    valid[k] = False
                    left -= 1
            self._in_dropout = left
            out[~valid] = np.nan
        self.frames += n
        self.dropouts += int((~valid).sum())
        return MocapFrames(t, out, valid)


def _ou_bias(w: np.ndarray, a: float, last: np.ndarray) -> np.ndarray:
    """(n, 22) bias of the frames: b_k = w_k + a b_(k-1) from ``last``, the first-order recursion frame by
    frame. The same bits as scipy.signal.lfilter([1], [1, -a], w, axis=0, zi=a * last), whose import costs
    every process two seconds (tests/test_worker_stream.py)."""
    out = np.empty_like(w)
    prev = last
    for k in range(len(w)):
        prev = out[k] = w[k] + a * prev
    return out


class MotionPlayback:
    """Drives the human in a scene from a trajectory of true angles (kinematically, never by forces).

    ``apply(data, t)`` poses the human at the linearly interpolated angles at time ``t`` [s] (with the
    matching joint velocities for an articulated human); with ``kinematics=True`` it also runs
    ``mj_kinematics``, as mink's ``Configuration.update`` does. Call it before each physics step so a held
    part follows the hand. ``human``: a workcell's :class:`~ergosim.human.mocap.MocapHuman`, or by default
    the :class:`HumanModel` of a ``model`` that has the human's joints.
    """

    def __init__(self, model: mujoco.MjModel, human: HumanModel | MocapHuman | None = None) -> None:
        self.model = model
        self.human = human if human is not None else HumanModel(model)
        self._t: np.ndarray | None = None
        self._q: np.ndarray | None = None
        self._qd: np.ndarray | None = None

    def load(self, t: np.ndarray, angles_deg: np.ndarray, stance: np.ndarray | None = None) -> None:
        """Set the trajectory: (n,) times [s], (n, 22) true angles [deg] and (n, 4) stance [m, m, deg, deg]
        (None: on the spot)."""
        self._t = np.asarray(t, dtype=float)
        self._q = body_qpos(angles_deg, stance)
        dt = np.diff(self._t)[:, None]
        rates = np.diff(self._q, axis=0) / np.where(dt > 0, dt, 1.0)
        self._qd = np.vstack([rates, np.zeros((1, self._q.shape[1]))])

    def apply(self, data: mujoco.MjData, t: float, kinematics: bool = False) -> None:
        if self._t is None:
            return
        k = int(np.clip(np.searchsorted(self._t, t, side="right") - 1, 0, len(self._t) - 1))
        if k + 1 < len(self._t):
            f = (t - self._t[k]) / max(self._t[k + 1] - self._t[k], 1e-12)
            f = min(max(f, 0.0), 1.0)
            q = self._q[k] + f * (self._q[k + 1] - self._q[k])
            qd = self._qd[k]
        else:
            q, qd = self._q[-1], np.zeros_like(self._q[-1])
        self.human.pose(data, q, qd)
        if kinematics:
            mujoco.mj_kinematics(self.model, data)
