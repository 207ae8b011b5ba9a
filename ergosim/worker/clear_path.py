"""Transitions that keep the body out of the furniture: a via posture where a straight transition passes
through it.

Between two key poses the body follows a minimum-jerk transition in joint space
(:mod:`ergosim.worker.minimum_jerk`). From the rest posture, hands hanging below a bench's top, to above a
part on the bench, that straight line in joint space swings the forearm up through the bench's edge. A
person lifts the hand first. Where a transition's sampled postures come closer than 0 to an obstacle, the
transition gets a via posture at its middle: the whole-body IK's answer for the hand at the middle of its
path lifted above the furniture, and the transition becomes

    q(τ) = q_a + (q_b - q_a) s(τ) + (q_via - (q_a + q_b) / 2) β(τ),    β(τ) = 16 τ² (1 - τ)²,

which passes through the via posture at τ = 1/2 (where s = 1/2) with the minimum-jerk profile's ends
untouched (β and its slope vanish at both ends): the hand rises on its way without stopping. The lift
grows by :data:`LIFT_STEP` until the transition is clear or :data:`MAX_LIFTS` tries are spent.

What a lift does not clear (an upper arm brushing a bench's edge while the body turns) is pushed out where
it is deepest: the IK, with the furniture as hard limits, finds the posture that keeps that frame's hand
where it is and the body out of the furniture, and the transition bends towards it with a bump that peaks at
that frame (rising and falling with the minimum-jerk profile, so the transition's ends are untouched);
:data:`MAX_PUSHES` times at most.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ergosim.worker.obstacles import IKModel, clearance

if TYPE_CHECKING:
    from ergosim.worker.ik import WholeBodyIK
    from ergosim.worker.ik_prior import IKPrior

__all__ = ["bump", "peak", "clear_transitions", "LIFT_STEP", "MAX_LIFTS", "MAX_PUSHES"]

LIFT_STEP = 0.08
"""m the hand's via point rises per try (assumed)."""
VIA_ABOVE = 0.08
"""m the via point starts above the top of the furniture under the hand (assumed: the forearm's radius and
a hand's width)."""
NEAR = 0.15
"""m: furniture within this horizontal distance of the hand's midway point counts as under it."""
MAX_PUSHES = 5
PEAK_RANGE = (0.1, 0.9)
"""Where a push's bump may peak within a transition: a frame closer to a key pose is pushed by a bump that
peaks here, scaled so that frame gets the whole correction."""
MAX_LIFTS = 4


def bump(tau: np.ndarray) -> np.ndarray:
    """β(τ) = 16 τ² (1 - τ)²: 0 with zero slope at both ends, 1 at τ = 1/2; 0 outside [0, 1]."""
    t = np.clip(tau, 0.0, 1.0)
    return 16.0 * t * t * (1.0 - t) ** 2


def peak(tau: np.ndarray, at: float) -> np.ndarray:
    """A bump that is 1 at ``at`` (0 < at < 1) and 0 with zero slope at 0 and 1: the minimum-jerk rise
    s(τ / at) before, the fall s((1 - τ) / (1 - at)) after."""
    from ergosim.worker.minimum_jerk import min_jerk  # noqa: PLC0415 - a sibling; kept next to its use

    t = np.clip(tau, 0.0, 1.0)
    return np.where(t <= at, min_jerk(t / at), min_jerk((1.0 - t) / (1.0 - at)))


def _tops_near(ik: WholeBodyIK, hand: np.ndarray, obstacles: tuple[int, ...]) -> list[float]:
    """Top heights [m] of the obstacle boxes within :data:`NEAR` of ``hand`` horizontally."""
    m, d = ik.model, ik.data
    tops = []
    for o in obstacles:
        rot = d.geom_xmat[o].reshape(3, 3)
        local = rot.T @ (hand - d.geom_xpos[o])
        half = m.geom_size[o]
        gap = np.maximum(np.abs(local[:2]) - half[:2], 0.0)
        if float(np.hypot(*gap)) <= NEAR:
            tops.append(float(d.geom_xpos[o][2] + half[2]))
    return tops


def _clearances(ik: WholeBodyIK, bodies: np.ndarray, built: IKModel) -> np.ndarray:
    out = np.empty(len(bodies))
    for k, b in enumerate(bodies):
        ik._fk(ik.qpos(b))
        out[k] = clearance(ik.model, ik.data, built.segments, built.obstacles, built.forearms)
    return out


def _min_clearance(ik: WholeBodyIK, bodies: np.ndarray, built: IKModel) -> float:
    """The smallest clearance along ``bodies``; -inf where one of them is out of balance (such a transition
    is never the better one)."""
    if float(ik.balance_path(bodies).min()) < 0.0:
        return -np.inf
    return float(_clearances(ik, bodies, built).min())


def _push_out(ik: WholeBodyIK, seg: np.ndarray, tau: np.ndarray, side: str, prior: IKPrior,
              built: IKModel) -> tuple[float, np.ndarray]:
    """``seg`` (m, 27), one transition's postures at normalised times ``tau``, bent out of the furniture
    where it passes through it (the module docstring): (its smallest clearance, the postures). A push that
    does not leave the transition clearer is not kept."""
    clear = _clearances(ik, seg, built)
    for _ in range(MAX_PUSHES):
        worst = int(np.argmin(clear))
        if clear[worst] >= 0.0 or not 0.0 < tau[worst] < 1.0:
            break
        hand = ik.hand_pos(seg[worst], side)
        out = ik.solve(seg[worst], hand, side, prior=prior, max_iter=30).body
        at = float(np.clip(tau[worst], *PEAK_RANGE))
        weight = peak(tau, at)
        weight = weight / max(float(weight[worst]), 1e-3)
        trial = ik.clip(seg + (out - seg[worst])[None, :] * np.minimum(weight, 1.0)[:, None])
        trial_clear = _clearances(ik, trial, built)
        if trial_clear.min() <= clear.min() or ik.balance_path(trial).min() < 0.0:
            break
        seg, clear = trial, trial_clear
    return float(clear.min()), seg


def clear_transitions(ik: WholeBodyIK, key_t: np.ndarray, keys: np.ndarray, t: np.ndarray, body: np.ndarray,
                      which: Sequence[int], side: str, prior: IKPrior, built: IKModel | None) -> np.ndarray:
    """``body`` (n, 27), sampled at ``t`` from the key poses ``keys`` at ``key_t``, with a via posture added
    to each transition of ``which`` (indices of key-pose segments) that passes through an obstacle of
    ``built`` (None: no obstacles)."""
    if built is None or not built.obstacles:
        return body
    out = body.copy()
    for k in which:
        t0, t1 = key_t[k], key_t[k + 1]
        inside = (t >= t0) & (t <= t1)
        if t1 <= t0 or not inside.any():
            continue
        start = _min_clearance(ik, out[inside], built)
        if start >= 0.0:
            continue
        tau = (t[inside] - t0) / (t1 - t0)
        mid = 0.5 * (keys[k] + keys[k + 1])
        hand = ik.hand_pos(mid, side)
        top = max([hand[2]] + _tops_near(ik, hand, built.obstacles))
        best = None
        for lift in range(MAX_LIFTS):
            via = ik.solve(mid, np.array([hand[0], hand[1], top + VIA_ABOVE + lift * LIFT_STEP]), side,
                           prior=prior, max_iter=30, collide=False).body
            trial = ik.clip(body[inside] + (via - mid)[None, :] * bump(tau)[:, None])
            clear = _min_clearance(ik, trial, built)
            if best is None or clear > best[0]:
                best = (clear, trial)
            if clear >= 0.0:
                break
        if best[0] < 0.0:
            best = max(best, _push_out(ik, best[1], tau, side, prior, built), key=lambda b: b[0])
        if best[0] > start:  # a via or a push that leaves the transition no clearer is not kept
            out[inside] = best[1]
    return out
