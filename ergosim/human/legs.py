"""The legs: a knee angle and the shanks' lean over the flat feet set where the pelvis is, and both legs.

The feet stand flat where the stance puts them. Each leg is a planar two-link chain from the ankle: the
shank leans forward over the foot by the ankle dorsiflexion φ, the knee flexes by κ, so the thigh leans
back from the knee by ψ = κ - φ, which is the hip flexion that keeps the pelvis upright. The hip joint
centre then sits, relative to where it is when standing straight,

    shift(κ, φ) = L_s sin φ - L_t sin(κ - φ)          forward [m]
    drop(κ, φ)  = L_s (1 - cos φ) + L_t (1 - cos(κ - φ))   down [m]

with L_t, L_s the thigh and shank lengths (Drillis & Contini: 0.245 H and 0.246 H). φ = κ / 2 keeps the
hip over the ankle (a squat); φ < 0 leans the shanks back and moves the hips back behind the feet, as a
person does when the trunk bends forward (a stoop), which keeps the centre of mass over the feet. The
left leg mirrors the right. The two leg angles are the stance's ``knee_flexion`` and
``ankle_dorsiflexion`` (:data:`ergosim.posture.STANCE`); everything else here follows them.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.errors import ModelError

__all__ = ["Legs", "DRIVEN"]

DRIVEN = ("pelvis_shift", "pelvis_drop", "hip_flexion", "left_hip_flexion", "left_knee_flexion",
          "left_ankle_dorsiflexion")
"""The joints set from the knee and the ankle, in the order of :meth:`Legs.driven` and its Jacobian."""


class Legs:
    """The leg joints of a compiled model that contains the human. ``write(qpos, knee, ankle)`` sets the
    knee, the ankle and every joint of :data:`DRIVEN` [rad, m] from the knee flexion and the ankle
    dorsiflexion [rad] (floats, or (n,) against (n, nq) ``qpos``). ``thigh``, ``shank``: lengths [m]."""

    def __init__(self, model: mujoco.MjModel) -> None:
        def adr(name: str) -> int:
            j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if j < 0:
                raise ModelError(f"the model has no human joint {name!r}", where="Legs")
            return int(model.jnt_qposadr[j])

        self.knee = adr("knee_flexion")
        self.ankle = adr("ankle_dorsiflexion")
        self.driven_adr = np.array([adr(n) for n in DRIVEN])
        self.thigh = float(-model.body("human_right_shank").pos[2])
        self.shank = float(-model.body("human_right_foot").pos[2])

    @property
    def length(self) -> float:
        """Thigh + shank [m]."""
        return self.thigh + self.shank

    def hip(self, knee: np.ndarray | float, ankle: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """(shift forward, drop) of the hip joint centre [m] from standing straight."""
        knee, ankle = np.asarray(knee, dtype=float), np.asarray(ankle, dtype=float)
        psi = knee - ankle
        shift = self.shank * np.sin(ankle) - self.thigh * np.sin(psi)
        drop = self.shank * (1.0 - np.cos(ankle)) + self.thigh * (1.0 - np.cos(psi))
        return shift, drop

    def driven(self, knee: float, ankle: float) -> tuple[np.ndarray, np.ndarray]:
        """The :data:`DRIVEN` values (6,) [m, m, rad...] and their Jacobian (6, 2) by (knee, ankle)."""
        psi = knee - ankle
        shift, drop = self.hip(knee, ankle)
        values = np.array([float(shift), float(drop), psi, psi, knee, ankle])
        ct, st = self.thigh * np.cos(psi), self.thigh * np.sin(psi)
        cs, ss = self.shank * np.cos(ankle), self.shank * np.sin(ankle)
        jac = np.array([
            [-ct, cs + ct],  # d shift / d(knee, ankle)
            [st, ss - st],  # d drop
            [1.0, -1.0],  # hip flexion
            [1.0, -1.0],
            [1.0, 0.0],  # the left knee
            [0.0, 1.0],  # the left ankle
        ])
        return values, jac

    def write(self, qpos: np.ndarray, knee: np.ndarray | float, ankle: np.ndarray | float = 0.0) -> None:
        """Set the knee, the ankle and every joint that follows them in ``qpos`` ((nq,) or (n, nq)) in
        place."""
        knee = np.asarray(knee, dtype=float)
        ankle = np.broadcast_to(np.asarray(ankle, dtype=float), knee.shape)
        shift, drop = self.hip(knee, ankle)
        psi = knee - ankle
        qpos[..., self.knee] = knee
        qpos[..., self.ankle] = ankle
        for a, v in zip(self.driven_adr, (shift, drop, psi, psi, knee, ankle), strict=True):
            qpos[..., a] = v
