"""The legs follow the knee: one knee angle sets the pelvis's height and both legs, with the feet flat.

A worker bends the knees symmetrically with the trunk upright over the feet. With the thigh turned forward
by half the knee angle at the hip and the foot back by the other half at the ankle, the shank leans
forward by half the knee angle, and thigh and shank of equal length keep the hip straight over the ankle.
The pelvis then lowers by

    drop(κ) = (thigh + shank) (1 - cos(κ / 2))

so a knee flexion κ of 60 deg lowers a 1.75 m person's hips by 11.5 cm. Drillis & Contini's thigh (0.245 H)
and shank (0.246 H) differ by 0.001 H, so the ankle moves by at most 1.5 mm: the feet stay where they stand.

The inverse, ``knee(drop)``, lets a solver move the pelvis height (a smooth variable whose Jacobian does
not vanish with straight legs, as the knee angle's does) and report the knee angle.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.errors import ModelError

__all__ = ["Legs"]


class Legs:
    """The knee-driven joints of a compiled model that contains the human: ``write(qpos, knee)`` sets the
    pelvis drop [m], both hips, both knees and both ankles [rad] from the knee angle ``knee`` [rad]
    (a float, or (n,) against (n, nq) ``qpos``). ``length``: thigh + shank [m]."""

    def __init__(self, model: mujoco.MjModel) -> None:
        def adr(name: str) -> int:
            j = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if j < 0:
                raise ModelError(f"the model has no human joint {name!r}", where="Legs")
            return int(model.jnt_qposadr[j])

        self.knee = adr("knee_flexion")
        self.drop_adr = adr("pelvis_drop")
        self.half = np.array([adr(n) for n in ("hip_flexion", "ankle_dorsiflexion", "left_hip_flexion",
                                              "left_ankle_dorsiflexion")])
        self.left_knee = adr("left_knee_flexion")
        thigh = -model.body("human_right_shank").pos[2]
        shank = -model.body("human_right_foot").pos[2]
        self.length = float(thigh + shank)

    def drop(self, knee: np.ndarray | float) -> np.ndarray | float:
        """How far the pelvis lowers [m] for knee flexion ``knee`` [rad]."""
        return self.length * (1.0 - np.cos(0.5 * np.asarray(knee)))

    def knee_of(self, drop: np.ndarray | float) -> np.ndarray | float:
        """The knee flexion [rad] that lowers the pelvis by ``drop`` [m] (the inverse of :meth:`drop`)."""
        return 2.0 * np.arccos(np.clip(1.0 - np.asarray(drop) / self.length, -1.0, 1.0))

    def write(self, qpos: np.ndarray, knee: np.ndarray | float) -> None:
        """Set the knee and every joint that follows it in ``qpos`` ((nq,) or (n, nq)) in place."""
        knee = np.asarray(knee, dtype=float)
        qpos[..., self.knee] = knee
        qpos[..., self.left_knee] = knee
        qpos[..., self.drop_adr] = self.drop(knee)
        half = 0.5 * knee
        for a in self.half:
            qpos[..., a] = half
