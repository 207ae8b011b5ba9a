"""Where the worker stands: the standing area, and the stance chosen for each reach before the posture.

The worker stands at the cell's worker position and may step and turn within a *standing area*
(:class:`StandingArea`, bounds on the stance's pelvis_x, pelvis_y [m] and pelvis_rotation [deg] of
:data:`ergosim.posture.STANCE`). A cell gives it in ``[worker]`` (``standing_area``, ``max_turn``); by default
it is the floor within one step of the spot that the body can occupy: a square of one step either way,
cut back where the body (a disc of :data:`BODY_RADIUS` times the stature around the pelvis) would enter a
table's or shelf's footprint. A step is 0.41 of the stature (:data:`STEP_FRACTION`: the common
step-length rule, about 0.72 m for a 1.75 m person; the body moves a whole step when one foot steps out
and the other follows); ``max_turn`` 90 deg, the largest single Turn Body of MTM-1 (TBC, 45-90 deg).

**The stance comes first** (:func:`choose_stance`), as in the HUMOSIM framework (Reed, Faraway & Chaffin)
and the posture prediction of Jack: where the feet go is decided from the target, and the whole-body IK
then solves the posture for that stance (:mod:`ergosim.worker.ik`). The rules:

- **Face the target** when it lies more than :data:`TURN_FROM_DEG` to the side (MTM-1 Turn Body starts at
  45 deg; below it the trunk, the neck and the eyes take the turn).
- **Step towards it** when it lies beyond the arm's reach from the acting shoulder, horizontally
  (:data:`STEP_FROM_REACH`), so that it ends :data:`WORK_REACH` of the arm's reach from that shoulder; the
  step stays inside the standing area, which keeps the body clear of the furniture. A target within reach
  is worked from where the worker stands: the worker never steps away from what it reaches for.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable

import numpy as np

from ergosim.errors import ConfigError

__all__ = ["StandingArea", "BODY_RADIUS", "STEP_FRACTION", "MAX_TURN_DEG", "area_from_footprints",
           "area_of_cell", "rotated_footprint", "StanceRule", "choose_stance", "TURN_FROM_DEG",
           "STEP_FROM_REACH", "WORK_REACH"]

BODY_RADIUS = 0.085
"""The body's half-depth around the pelvis, as a fraction of stature (0.15 m at 1.75 m: the model's spine
capsule, 0.065 H, plus 0.02 H of clothing and clearance; assumed)."""
STEP_FRACTION = 0.41
"""How far the body moves in one step, as a fraction of stature: a walking step of 0.41 H (the common
step-length rule; assumed for a worker at a bench)."""
TURN_FROM_DEG = 45.0
"""A target more than this far to the side [deg] is faced by turning the body (MTM-1 Turn Body, TBC, from
45 deg)."""
STEP_FROM_REACH = 1.0
"""A target farther than this share of the arm's reach from the acting shoulder, horizontally, is stepped
towards (assumed: beyond the straight arm's reach only a deep lean would get the hand there)."""
WORK_REACH = 0.7
"""The share of the arm's reach, horizontally from the acting shoulder, at which the worker stops before a
target it steps towards (assumed: the hand then works with the elbow bent, inside the comfortable reach
envelope)."""
KNEE_FRACTION, SHOULDER_FRACTION = 0.285, 0.818
"""Knee and shoulder heights as fractions of stature (Drillis & Contini): furniture between them blocks the
body."""
MAX_TURN_DEG = 90.0
"""The largest turn of the body in place [deg]: MTM-1 Turn Body, case 1 or 2, covers 45-90 deg."""


@dataclasses.dataclass(frozen=True)
class StandingArea:
    """Bounds of the stance in the worker's frame: ``x``, ``y`` [m] of the pelvis, ``turn`` [deg]. An area
    with no extent (:meth:`planted`) keeps the feet where they are."""

    x: tuple[float, float] = (0.0, 0.0)
    y: tuple[float, float] = (0.0, 0.0)
    turn: tuple[float, float] = (0.0, 0.0)

    @classmethod
    def planted(cls) -> StandingArea:
        """No step and no turn: the stance stays where it is."""
        return cls()

    @property
    def is_planted(self) -> bool:
        return self.x[0] == self.x[1] and self.y[0] == self.y[1] and self.turn[0] == self.turn[1]

    def bounds(self, stance: np.ndarray) -> list[tuple[float, float]]:
        """[(lo, hi)] of pelvis_x, pelvis_y [m] and pelvis_rotation [deg] for a solve that starts at
        ``stance`` (4,): the area, or that very stance when the area is planted."""
        if self.is_planted:
            return [(float(stance[k]), float(stance[k])) for k in range(3)]
        return [self.x, self.y, self.turn]

    def contains(self, stance: np.ndarray, tol: float = 1e-9) -> bool:
        (x0, x1), (y0, y1), (t0, t1) = self.x, self.y, self.turn
        x, y, t = stance[:3]
        return x0 - tol <= x <= x1 + tol and y0 - tol <= y <= y1 + tol and t0 - tol <= t <= t1 + tol


def area_from_footprints(footprints: Iterable[tuple[np.ndarray, np.ndarray]], stature: float,
                         max_turn: float = MAX_TURN_DEG) -> StandingArea:
    """The default standing area: ± one step around the spot (the worker's frame's origin), each side cut
    back where the body would enter a footprint. ``footprints``: (centre (2,), half-size (2,)) rectangles
    [m] in the worker's frame, axis-aligned with it (furniture turned against the worker is bounded by its
    enclosing rectangle)."""
    step = STEP_FRACTION * stature
    r = BODY_RADIUS * stature
    lo = np.array([-step, -step])
    hi = np.array([step, step])
    for centre, half in footprints:
        c, h = np.asarray(centre, dtype=float), np.asarray(half, dtype=float) + r
        if np.all(np.abs(c) < h):
            continue  # the spot itself is inside (a shelf the worker stands under): not a wall to cut by
        if not np.all((c - h < hi) & (c + h > lo)):
            continue
        # cut the side that loses the least: move one bound of one axis to the footprint's near edge
        best = None
        for axis in range(2):
            if c[axis] - h[axis] >= 0.0:
                cut = ("hi", axis, c[axis] - h[axis])
                loss = hi[axis] - cut[2]
            elif c[axis] + h[axis] <= 0.0:
                cut = ("lo", axis, c[axis] + h[axis])
                loss = cut[2] - lo[axis]
            else:
                continue
            if best is None or loss < best[0]:
                best = (loss, cut)
        if best is None:
            continue
        side, axis, value = best[1]
        if side == "hi":
            hi[axis] = min(hi[axis], max(value, 0.0))
        else:
            lo[axis] = max(lo[axis], min(value, 0.0))
    return StandingArea((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1])),
                        (-float(max_turn), float(max_turn)))


def rotated_footprint(centre_w: np.ndarray, half_w: np.ndarray, yaw_deg: float, origin_w: np.ndarray,
                      frame_yaw_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """A world rectangle (centre, half-size, its yaw) as the axis-aligned rectangle enclosing it in a frame
    at ``origin_w`` turned by ``frame_yaw_deg``."""
    a = math.radians(yaw_deg - frame_yaw_deg)
    f = math.radians(frame_yaw_deg)
    rel = np.asarray(centre_w, dtype=float) - np.asarray(origin_w, dtype=float)
    c = np.array([math.cos(f) * rel[0] + math.sin(f) * rel[1], -math.sin(f) * rel[0] + math.cos(f) * rel[1]])
    hx, hy = half_w
    ca, sa = abs(math.cos(a)), abs(math.sin(a))
    half = np.array([ca * hx + sa * hy, sa * hx + ca * hy])
    return c, half


def area_of_cell(spec, stature: float) -> StandingArea:
    """The standing area of a cell (:class:`~ergosim.scenes.cellspec.CellSpec`) for a worker of ``stature``
    [m]: its ``[worker] standing_area`` and ``max_turn``, or the clear floor within one step (furniture
    whose solid parts span the body between knee and shoulder height bounds it)."""
    w = spec.worker
    turn = MAX_TURN_DEG if w.max_turn is None else float(w.max_turn)
    if not 0.0 <= turn <= 180.0:
        raise ConfigError(f"max_turn must be within 0..180 deg, got {turn}", where="worker.max_turn")
    if w.standing_area is not None:
        x0, x1, y0, y1 = (float(v) for v in w.standing_area)
        if not (x0 <= 0.0 <= x1 and y0 <= 0.0 <= y1):
            raise ConfigError(f"standing_area {w.standing_area} must contain the worker's spot: "
                              "x_min <= 0 <= x_max and y_min <= 0 <= y_max", where="worker.standing_area")
        return StandingArea((x0, x1), (y0, y1), (-turn, turn))
    low, high = KNEE_FRACTION * stature, SHOULDER_FRACTION * stature
    feet = [rotated_footprint(c[:2], h[:2], yaw, w.xy, w.yaw)
            for f in spec.furniture for c, h, yaw in f.boxes() if c[2] - h[2] < high and c[2] + h[2] > low]
    return area_from_footprints(feet, stature, turn)


@dataclasses.dataclass(frozen=True)
class StanceRule:
    """What the stance rules need of the body [m]: the arm's reach (shoulder to the grasp point with the
    arm straight), the acting shoulder's offset to the left of the midline (negative for the right arm),
    and the knee's height (below it the worker squats, :func:`ergosim.worker.ik_prior.squat_prior`)."""

    arm_reach: float
    shoulder_y: float
    knee_height: float


def choose_stance(point: np.ndarray, rule: StanceRule, area: StandingArea) -> np.ndarray:
    """(pelvis_x, pelvis_y [m], pelvis_rotation [deg]) from which to reach ``point`` (3,) [m, the worker's
    frame], by the rules of the module docstring, within ``area`` (a planted area keeps the spot)."""
    if area.is_planted:
        return np.zeros(3)
    az = math.degrees(math.atan2(point[1], point[0]))
    turn = az if abs(az) > TURN_FROM_DEG else 0.0
    turn = min(max(turn, area.turn[0]), area.turn[1])
    c, s = math.cos(math.radians(turn)), math.sin(math.radians(turn))
    shoulder = np.array([-s * rule.shoulder_y, c * rule.shoulder_y])
    to_point = np.asarray(point[:2], dtype=float) - shoulder
    dist = float(np.linalg.norm(to_point))
    if dist <= STEP_FROM_REACH * rule.arm_reach:
        return np.array([0.0, 0.0, turn])
    direction = to_point / dist
    step = direction * (dist - WORK_REACH * rule.arm_reach)
    # stay in the area along the line of the step (never past its edge, never backwards)
    scale = 1.0
    for k, (lo, hi) in enumerate((area.x, area.y)):
        if step[k] > 1e-12:
            scale = min(scale, hi / step[k])
        elif step[k] < -1e-12:
            scale = min(scale, lo / step[k])
    step = step * max(scale, 0.0)
    return np.array([step[0], step[1], turn])
