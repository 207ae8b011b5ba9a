"""Balance: the whole body's centre of mass stays over the base of support of the feet.

A person standing still keeps the vertical projection of the whole-body centre of mass inside the base of
support, the area the two flat feet span on the floor (the static stability condition of biomechanics and
of posture-prediction tools; AnyBody keeps the centre of pressure there, Jack and HUMOSIM check the centre
of mass). With the feet side by side where the stance puts them, the base of support is a rectangle in the
stance's frame (x along the feet, y to the left):

- along the feet, from the heel to the toe tip: a quarter of the foot's length (Drillis & Contini, 0.152 H)
  behind the ankle and three quarters in front (:func:`ergosim.human.mjcf.foot_extent`);
- across, from the outer edge of one foot to the other: the ankles 0.55 of the hip half-width off the
  midline (the model's feet) plus half the foot's width, 0.055 H (Drillis & Contini).

:class:`BalanceLimit` is a mink limit: the centre of mass's linearised motion may not carry it closer to an
edge than :data:`BALANCE_MARGIN`. :meth:`SupportPolygon.margin` measures a posture: the distance from the
centre of mass's projection to the nearest edge [m], negative outside; :func:`rebalance` brings the frames of
a motion that stray outside back in.
"""

from __future__ import annotations

import mink
import mujoco
import numpy as np

from ergosim.human.model import ROOT_BODY

__all__ = ["BALANCE_MARGIN", "FOOT_WIDTH", "SupportPolygon", "BalanceLimit", "rebalance"]

BALANCE_MARGIN = 0.02
"""m the centre of mass keeps from the edge of the base of support (assumed: a small static margin for a
person standing at work)."""
FOOT_WIDTH = 0.055
"""Foot width as a fraction of stature (Drillis & Contini 1966, via Winter 2009 Fig. 4.1)."""


class SupportPolygon:
    """The base of support of a compiled model's human: the rectangle the feet span, in the stance frame
    (the feet's ``human_right_foot``/``human_left_foot`` bodies give where they are and face)."""

    def __init__(self, model: mujoco.MjModel, stature: float, foot_length: float) -> None:
        self.model = model
        self.root = model.body(ROOT_BODY).id
        self.feet = (model.body("human_right_foot").id, model.body("human_left_foot").id)
        self.heel, self.toe = -0.25 * foot_length, 0.75 * foot_length
        self.half_width = 0.5 * FOOT_WIDTH * stature
        self._jac = np.zeros((3, model.nv))

    def frame(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """(centre (2,) between the ankles, heading unit vector (2,)) of the feet in the world [m]."""
        r, left = data.xpos[self.feet[0]], data.xpos[self.feet[1]]
        x = data.xmat[self.feet[0]].reshape(3, 3)[:2, 0]
        return 0.5 * (r[:2] + left[:2]), x / max(float(np.linalg.norm(x)), 1e-12)

    def com_local(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The centre of mass in the feet's frame (2,) [m], the frame's rotation (2, 2) world -> local, and
        the half-extents: (lo (2,), hi (2,)) of the base of support in that frame."""
        centre, ux = self.frame(data)
        rot = np.array([[ux[0], ux[1]], [-ux[1], ux[0]]])
        com = rot @ (data.subtree_com[self.root][:2] - centre)
        half_y = 0.5 * float(np.linalg.norm(data.xpos[self.feet[1]][:2] - data.xpos[self.feet[0]][:2]))
        lo = np.array([self.heel, -half_y - self.half_width])
        hi = np.array([self.toe, half_y + self.half_width])
        return com, rot, np.stack([lo, hi])

    def margin(self, data: mujoco.MjData) -> float:
        """Distance [m] from the centre of mass's projection to the nearest edge (negative outside); the
        kinematics and ``mj_comPos`` must be current."""
        com, _, (lo, hi) = self.com_local(data)
        return float(min(com[0] - lo[0], hi[0] - com[0], com[1] - lo[1], hi[1] - com[1]))

    def com_jacobian(self, data: mujoco.MjData) -> np.ndarray:
        """(3, nv) Jacobian of the whole body's centre of mass."""
        mujoco.mj_jacSubtreeCom(self.model, data, self._jac, self.root)
        return self._jac


class BalanceLimit(mink.Limit):
    """mink limit: the centre of mass moves no closer than ``margin`` to the edge of the base of support.
    Where it already is closer (a start outside), the step must bring it back by at least that much."""

    def __init__(self, polygon: SupportPolygon, margin: float = BALANCE_MARGIN) -> None:
        self.polygon = polygon
        self.margin = margin

    def compute_qp_inequalities(self, configuration: mink.Configuration, dt: float) -> mink.Constraint:
        data = configuration.data
        com, rot, (lo, hi) = self.polygon.com_local(data)
        jac = rot @ self.polygon.com_jacobian(data)[:2]  # (2, nv) in the feet's frame
        lo, hi = lo + self.margin, hi - self.margin
        g = np.vstack([jac, -jac])
        h = np.concatenate([hi - com, com - lo])
        return mink.Constraint(G=g, h=h)


def rebalance(ik, bodies: np.ndarray, iterations: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """``bodies`` (n, 27) with every frame out of balance brought back over the feet by the shanks' lean
    (the ankle, which moves the hips forward or back with the knees as they are): a standing person shifts
    the hips to keep the centre of mass over the feet throughout a movement, not only at its key postures.
    A transition between two balanced postures in joint space need not be balanced; this is the correction
    (a few Newton steps on the ankle per frame, :data:`BALANCE_MARGIN` inside the base of support).
    Returns the bodies and their (n,) balance margins [m]."""
    out = np.array(bodies, dtype=float)
    margins = ik.balance_path(out)
    ankle = out.shape[1] - 1
    lo, hi = ik.clip(np.full(out.shape[1], -1e9))[ankle], ik.clip(np.full(out.shape[1], 1e9))[ankle]
    for k in np.flatnonzero(margins < 0.0):
        for _ in range(iterations):
            x0, bound = _com_x(ik, out[k])
            if bound is None:
                break
            trial = out[k].copy()
            trial[ankle] += 0.5
            x1, _ = _com_x(ik, trial)
            slope = (x1 - x0) / 0.5
            if abs(slope) < 1e-6:
                break
            out[k, ankle] = float(np.clip(out[k, ankle] + (bound - x0) / slope, lo, hi))
    moved = np.flatnonzero(margins < 0.0)
    if moved.size:
        margins[moved] = ik.balance_path(out[moved])
    return out, margins


def _com_x(ik, body: np.ndarray) -> tuple[float, float | None]:
    """The centre of mass along the feet [m] and the nearest point it should move to (None: it is already
    inside the base of support with the margin)."""
    ik._fk(ik.qpos(body))
    mujoco.mj_comPos(ik.model, ik.data)
    com, _, (lo, hi) = ik.support.com_local(ik.data)
    lo, hi = lo[0] + BALANCE_MARGIN, hi[0] - BALANCE_MARGIN
    if lo <= com[0] <= hi:
        return float(com[0]), None
    return float(com[0]), float(min(max(com[0], lo), hi))
