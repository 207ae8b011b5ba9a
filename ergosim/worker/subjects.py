"""Seeded synthetic subjects: anthropometry, speed, posture style, sensor noise and KWear parameters.

Population figures: statures are normal per sex, 1.77 +- 0.07 m (men) and 1.64 +- 0.065 m (women), close to
European adult surveys (e.g. DINED / CAESAR); 2 of 12 subjects are women in expectation, as in the paper's
§7.2 cohort. Everything is drawn from the ``np.random.Generator`` passed in, so the same seed gives the same
subject bit for bit.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import mujoco
import numpy as np

from ergosim.errors import ConfigError
from ergosim.human.anthropometry import SEGMENT_SCALES
from ergosim.human.model import human_spec
from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.ik_prior import IKPrior, default_prior

__all__ = ["Subject", "make_subject", "make_subjects", "rest_angles", "FEMALE_FRACTION"]

_IDX = {n: i for i, n in enumerate(HUMAN_JOINTS)}


@dataclass(frozen=True)
class Subject:
    """One synthetic worker.

    stature [m]; ``scale``: per-segment multipliers (name, factor) pairs; ``speed``: movement-speed factor
    (> 1 faster); ``trunk_use``: posture style, > 1 stoops/twists sooner, < 1 reaches with the arm;
    ``elbow_comfort_deg``: how straight an arm may get before the trunk helps; ``eye_down_deg``: the
    preferred declination of the line of sight, taken by the eyes before the neck flexes (Hill & Kroemer
    1986); ``noise_deg``: white sensor noise; ``bias_deg``: drift of
    the sensor bias; ``variability_deg``: trial-to-trial variation of the preferred posture;
    ``timing_variability``: trial-to-trial variation of each movement's duration, the sigma of a log-normal
    factor (0.01 ~ +-1 %; 0 = the same timing every execution);
    ``kwear``: overrides of the KWear parameters (``KWearParams`` field -> value; empty = paper defaults).
    """

    name: str
    stature: float = 1.75
    scale: tuple[tuple[str, float], ...] = ()
    speed: float = 1.0
    trunk_use: float = 1.0
    elbow_comfort_deg: float = 25.0
    eye_down_deg: float = 29.0
    noise_deg: float = 1.0
    bias_deg: float = 1.5
    variability_deg: float = 0.6
    timing_variability: float = 0.01
    handedness: str = "right"
    kwear: tuple[tuple[str, float], ...] = field(default=())

    def __post_init__(self) -> None:
        if not 0.0 <= self.timing_variability <= 0.5:
            raise ConfigError(f"timing_variability must be in [0, 0.5], got {self.timing_variability}",
                              where=f"subject {self.name}")

    @property
    def scale_map(self) -> dict[str, float]:
        return dict(self.scale)

    @property
    def workcell_fields(self) -> dict[str, Any]:
        """The workcell fields, by dotted path, that build this subject's body in a scene (stature, segment
        scaling); any workcell file has them."""
        return {"worker.stature": self.stature, "worker.human_scale": self.scale}

    def spec(self, keyframe: str | None = "home") -> mujoco.MjSpec:
        """The subject's human body (attach it into a scene, or compile it on its own)."""
        return human_spec(self.stature, self.scale_map, keyframe=keyframe)

    def prior(self) -> IKPrior:
        """The IK posture prior of this subject's style."""
        return replace(default_prior(self.trunk_use, self.elbow_comfort_deg), eye_down_deg=self.eye_down_deg)

    def kwear_params(self) -> Any:
        """``ergosim.ergonomics.kwear.KWearParams`` with this subject's overrides."""
        from ergosim.ergonomics.kwear import KWearParams  # noqa: PLC0415 - lazy: ergonomics is optional here

        try:
            return KWearParams(**dict(self.kwear))
        except TypeError as err:
            raise ConfigError(f"bad KWear override for subject {self.name}: {err}",
                              where="Subject.kwear") from err


def rest_angles(subject: Subject | None = None) -> np.ndarray:
    """(22,) rest posture [deg]: upright, arms hanging relaxed, elbows slightly flexed, gaze a bit down."""
    q = np.zeros(len(HUMAN_JOINTS))
    q[_IDX["elbow_flexion"]] = q[_IDX["left_elbow_flexion"]] = 15.0
    q[_IDX["shoulder_flexion"]] = q[_IDX["left_shoulder_flexion"]] = 5.0
    q[_IDX["neck_flexion"]] = 8.0
    return q


FEMALE_FRACTION = 2.0 / 12.0
"""Share of women in a drawn population: the paper's §7.2 cohort, "2 females and 10 males"."""


def make_subject(rng: np.random.Generator, name: str = "S01", kwear: Mapping[str, float] | None = None, *,
                 female_fraction: float = FEMALE_FRACTION, pace: float = 1.0, **overrides: Any) -> Subject:
    """Draw one subject from ``rng``; keyword ``overrides`` fix any field (e.g. ``stature=1.62``).

    ``female_fraction``: probability that the subject is a woman (stature from the women's distribution);
    ``pace``: the population's mean performance, multiplying every drawn ``speed`` (1 = MTM-1 standard
    performance, :mod:`ergosim.worker.action_timing`)."""
    if not 0.0 <= female_fraction <= 1.0:
        raise ConfigError(f"female_fraction must be in [0, 1], got {female_fraction}", where="make_subject")
    if not pace > 0:
        raise ConfigError(f"pace must be > 0, got {pace}", where="make_subject")
    female = rng.random() < female_fraction
    stature = rng.normal(1.64, 0.065) if female else rng.normal(1.77, 0.07)
    scale = tuple((k, float(np.clip(rng.normal(1.0, 0.025), 0.92, 1.08))) for k in SEGMENT_SCALES)
    fields = dict(
        name=name,
        stature=float(np.clip(stature, 1.50, 2.00)),
        scale=scale,
        speed=pace * float(np.clip(rng.normal(1.0, 0.12), 0.75, 1.3)),
        trunk_use=float(np.clip(rng.lognormal(0.0, 0.2), 0.65, 1.6)),
        elbow_comfort_deg=float(np.clip(rng.normal(25.0, 5.0), 12.0, 40.0)),
        # Hill & Kroemer (1986): preferred line of sight 29 +- 12 deg below the head's horizontal; clipped
        # to one standard deviation either way
        eye_down_deg=float(np.clip(rng.normal(29.0, 12.0), 17.0, 41.0)),
        noise_deg=float(np.clip(rng.normal(1.0, 0.3), 0.3, 2.0)),
        bias_deg=float(np.clip(rng.normal(1.5, 0.5), 0.3, 3.0)),
        # Trial-to-trial variability, calibrated against §7.2: "repeat each action η = 3 times, which
        # ensured Ṽ_des < 1e-3" (docs/fidelity.md); a drawn subject varies its posture by ~0.6 deg and its
        # timing by 1 % (timing_variability) from one execution to the next.
        variability_deg=float(np.clip(rng.normal(0.6, 0.16), 0.2, 1.2)),
        kwear=tuple(sorted((kwear or {}).items())),
    )
    # not drawn: the population keeps the timing jitter it was built with; override it per subject
    unknown = set(overrides) - set(fields) - {"handedness", "timing_variability"}
    if unknown:
        raise ConfigError(f"unknown subject field(s) {sorted(unknown)}", where="make_subject")
    fields.update(overrides)
    if "scale" in overrides and isinstance(overrides["scale"], Mapping):
        fields["scale"] = tuple(sorted(overrides["scale"].items()))
    return Subject(**fields)


def make_subjects(n: int, seed: int, kwear: Mapping[str, float] | None = None,
                  **population: Any) -> list[Subject]:
    """``n`` subjects S01..Sn; subject i depends only on (seed, i), so adding subjects keeps the others.
    ``population``: ``female_fraction`` and ``pace`` of :func:`make_subject`."""
    return [make_subject(np.random.default_rng([seed, i]), f"S{i + 1:02d}", kwear=kwear, **population)
            for i in range(n)]
