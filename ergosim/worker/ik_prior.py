"""The posture priors of the whole-body IK: where each joint prefers to be, how freely it moves, where the
eyes take the gaze.

Every joint j of the body vector (:data:`BODY`: the 22 posture angles, then the stance) costs
((q_j - pref_j) / sigma_j)^2: sigma is how far it moves for one unit of cost. The stance's step and turn
are not priced here: the stance is chosen first (:mod:`ergosim.worker.stance`) and the IK solves the body
for it, as posture-prediction tools do. The sources:

- **Trunk and neck: ISO 11226:2000 / EN 1005-4 neutral zones.** Trunk inclination is neutral from 0 to
  20 deg, trunk lateral bending and twisting up to 10 deg ("not clearly visible"), neck flexion from 0 to
  25 deg and neck lateral bending up to 10 deg (as tabulated by Wagner et al., J Occup Med Toxicol 2020,
  Table 2). One unit of cost is the edge of the joint's neutral zone; a subject's ``trunk_use`` scales the
  trunk's. Extension of the trunk or the neck is outside the neutral zone: it costs as a comfort-box
  excess. Neck rotation has no neutral zone there: 25 deg, the neck's flexion zone, is *assumed*. Neck
  flexion past :data:`NECK_COMFORT_DEG` costs as a comfort-box excess too, so the neck does not sit at
  its 45 deg limit while the trunk or the knees can take the gaze.
- **Eyes: Hill & Kroemer (1986), Ergonomics 29:1129.** The preferred line of sight lies 29 deg +- 12 deg
  below the horizontal of the head; the eyes take the gaze first, up to the subject's own preferred
  declination ``eye_down_deg`` (29 deg by default), 5 deg up and 15 deg sideways (*assumed*: gaze shifts up
  to 15-20 deg are made mostly by the eyes). Beyond that they still turn, softly: the rest of the gaze
  costs one unit per ``gaze_sigma_deg`` (12 deg, their spread), and the neck, the trunk and the knees share
  it by their own priors (Burgess-Limerick et al. 2000, Human Factors 42:90: lower targets are seen with
  both more eye declination and more head flexion).
- **Arm: assumed**: the elbow prefers 80 deg and costs more when almost straight (a one-sided comfort box
  at ``elbow_comfort_deg``), the shoulder abduction and rotation priors keep the elbow low, a shrug is
  allowed but costly.
- **Legs: assumed.** 30 deg of knee flexion and 15 deg of ankle dorsiflexion each cost one unit from
  straight legs: a worker stands straight until the trunk's or the neck's cost makes bending the knees or
  shifting the hips worth it; for a target below knee height the worker squats (:func:`squat_prior`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ergosim.posture import HUMAN_JOINTS, STANCE

__all__ = ["BODY", "IKPrior", "default_prior", "squat_prior", "TRUNK_NEUTRAL_DEG", "NECK_NEUTRAL_DEG",
           "STANCE_SIGMA", "NECK_COMFORT_DEG", "STOOP_KNEE_DEG", "SQUAT_KNEE_DEG", "PREFERRED_GAZE_DEG"]

BODY: tuple[str, ...] = HUMAN_JOINTS + STANCE
"""The body vector: posture angles [deg] then the stance [m, m, deg, deg, deg] (27)."""
_IDX = {n: i for i, n in enumerate(BODY)}

TRUNK_NEUTRAL_DEG = {"trunk_flexion": 20.0, "trunk_lateral_bend": 10.0, "trunk_rotation": 10.0}
"""ISO 11226:2000 / EN 1005-4: trunk inclination neutral 0-20 deg, side bending and twisting up to 10 deg."""
NECK_NEUTRAL_DEG = {"neck_flexion": 25.0, "neck_lateral_bend": 10.0, "neck_rotation": 25.0}
"""ISO 11226:2000: neck flexion neutral 0-25 deg, lateral bending up to 10 deg; rotation assumed (25 deg)."""
STANCE_SIGMA = {"knee_flexion": 30.0, "ankle_dorsiflexion": 15.0}
"""Assumed: 30 deg of knee flexion and 15 deg of ankle dorsiflexion each cost one unit [deg]."""
NECK_COMFORT_DEG = 35.0
"""Neck flexion [deg] past which each 4 deg more costs one unit (assumed: 10 deg inside the 45 deg range,
10 deg past ISO 11226's 25 deg neutral zone)."""
PREFERRED_GAZE_DEG = 29.0
"""Hill & Kroemer (1986): the preferred declination of the line of sight below the head's horizontal."""
STOOP_KNEE_DEG = 30.0
"""Knee flexion [deg] a worker reaching above knee height keeps within (a comfort box; assumed: the knees
bend slightly in a stoop, and MTM-1 counts a Bend past 30 deg, :mod:`ergosim.worker.action_timing`)."""
DEEP_SQUAT_KNEE_DEG = 110.0
"""Knee flexion [deg] past which a squat costs like a comfort-box excess (assumed: a full squat, the knee near
its 135 deg range, is held only briefly)."""
SQUAT_KNEE_DEG = 60.0
"""Knee flexion [deg] a squatting worker prefers (assumed: a semi-squat; the knees' cost is measured from
here, the ankles' from half of it, so the hips stay over the feet)."""


@dataclass(frozen=True)
class IKPrior:
    """Preferred values and their softness, (26,) each in :data:`BODY` order [deg, or m for the pelvis
    step], plus gaze sharing.

    Outside the comfort box [``comfort_lo``, ``comfort_hi``] a joint costs one unit per ``comfort_sigma_deg``
    more: an almost straight elbow or an arm behind the back is expensive. ``eye_down_deg``/``eye_up_deg``/
    ``eye_side_deg``: gaze the eyes take before the head must turn; beyond that the gaze error costs one unit
    per ``gaze_sigma_deg``.
    """

    pref: np.ndarray
    sigma: np.ndarray
    comfort_lo: np.ndarray
    comfort_hi: np.ndarray
    comfort_sigma_deg: float = 4.0
    eye_down_deg: float = PREFERRED_GAZE_DEG
    eye_up_deg: float = 5.0
    eye_side_deg: float = 15.0
    gaze_sigma_deg: float = 12.0

    def jittered(self, rng: np.random.Generator, deg: float) -> IKPrior:
        """A copy whose preferred posture angles are perturbed by N(0, deg) (trial-to-trial variability);
        the legs' preference is not."""
        pref = self.pref.copy()
        pref[:len(HUMAN_JOINTS)] += rng.normal(0.0, deg, len(HUMAN_JOINTS))
        return replace(self, pref=pref)


def default_prior(trunk_use: float = 1.0, elbow_comfort_deg: float = 25.0,
                  stance_sigma: dict[str, float] | None = None) -> IKPrior:
    """Natural priors; ``trunk_use`` > 1 is a person who bends/twists the trunk sooner (stoop style);
    ``stance_sigma`` overrides :data:`STANCE_SIGMA` entries."""
    n = len(BODY)
    pref = np.zeros(n)
    sigma = np.full(n, 30.0)
    lo_c = np.full(n, -360.0)
    hi_c = np.full(n, 360.0)
    hi_c[_IDX["neck_flexion"]] = NECK_COMFORT_DEG
    hi_c[_IDX["knee_flexion"]] = STOOP_KNEE_DEG
    box = {"elbow_flexion": (elbow_comfort_deg, 360.0), "shoulder_flexion": (-15.0, 360.0),
           "shoulder_abduction": (-25.0, 360.0)}
    # ISO 11226: trunk and neck extension lie outside their neutral zones (leaning back is "awkward")
    for name in ("trunk_flexion", "neck_flexion"):
        lo_c[_IDX[name]] = 0.0
    arm = {
        "shoulder_flexion": (15.0, 70.0),
        "shoulder_abduction": (8.0, 18.0),  # elbow stays low
        "shoulder_rotation": (25.0, 30.0),
        "shoulder_elevation": (0.0, 10.0),  # shrug only when needed
        "elbow_flexion": (80.0, 80.0),
        "forearm_pronation": (20.0, 35.0),
        "wrist_flexion": (0.0, 18.0),
        "wrist_deviation": (0.0, 12.0),
    }
    for prefix in ("", "left_"):
        for name, (p, s) in arm.items():
            pref[_IDX[prefix + name]], sigma[_IDX[prefix + name]] = p, s
        for name, (lo, hi) in box.items():
            lo_c[_IDX[prefix + name]], hi_c[_IDX[prefix + name]] = lo, hi
    for name, s in TRUNK_NEUTRAL_DEG.items():
        sigma[_IDX[name]] = s * trunk_use
    for name, s in NECK_NEUTRAL_DEG.items():
        sigma[_IDX[name]] = s
    for name, s in {**STANCE_SIGMA, **(stance_sigma or {})}.items():
        sigma[_IDX[name]] = s
    return IKPrior(pref, sigma, lo_c, hi_c)


def squat_prior(prior: IKPrior) -> IKPrior:
    """``prior`` for a target below knee height: the knees prefer :data:`SQUAT_KNEE_DEG` and the ankles
    half of it (the hips over the feet). The rule is the manual-handling advice to bend the knees rather
    than stoop for a low reach (HSE, *Manual handling at work*, INDG143: "a slight bending of the back,
    hips and knees ... is preferable to fully flexing the back (stooping)"): below the knee the worker
    squats, above it the legs stay straight unless bending them pays."""
    pref = prior.pref.copy()
    pref[_IDX["knee_flexion"]] = SQUAT_KNEE_DEG
    pref[_IDX["ankle_dorsiflexion"]] = 0.5 * SQUAT_KNEE_DEG
    hi_c = prior.comfort_hi.copy()
    hi_c[_IDX["knee_flexion"]] = DEEP_SQUAT_KNEE_DEG
    return replace(prior, pref=pref, comfort_hi=hi_c)
