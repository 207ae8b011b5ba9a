"""Where the worker may stand: the standing area in the worker's frame, from the cell's furniture.

The worker stands at the cell's worker position and may step and turn within a *standing area*
(:class:`StandingArea`, bounds on the stance's pelvis_x, pelvis_y [m] and pelvis_rotation [deg] of
:data:`ergosim.posture.STANCE`). A cell gives it in ``[worker]`` (``standing_area``, ``max_turn``); by default
it is the floor within one step of the spot that the body can occupy: a square of ``max_step`` either way,
cut back where the body (a disc of :data:`BODY_RADIUS` times the stature around the pelvis) would enter a
table's or shelf's footprint. ``max_step`` is a normal walking step, 0.41 of the stature (*assumed*: the
common step-length rule, about 0.72 m for a 1.75 m person, halved: the pelvis moves half a step when one
foot steps out and the other follows); ``max_turn`` 90 deg, the largest single Turn Body of MTM-1 (TBC,
45-90 deg).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable

import numpy as np

from ergosim.errors import ConfigError

__all__ = ["StandingArea", "BODY_RADIUS", "STEP_FRACTION", "MAX_TURN_DEG", "area_from_footprints",
           "area_of_cell", "rotated_footprint"]

BODY_RADIUS = 0.085
"""The body's half-depth around the pelvis, as a fraction of stature (0.15 m at 1.75 m: the model's spine
capsule, 0.065 H, plus 0.02 H of clothing and clearance; assumed)."""
STEP_FRACTION = 0.205
"""How far the pelvis moves in one step, as a fraction of stature: half a walking step of 0.41 H (assumed)."""
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
    feet = [rotated_footprint(c[:2], h[:2], 0.0, w.xy, w.yaw)
            for f in spec.furniture for c, h in f.boxes() if c[2] - h[2] < high and c[2] + h[2] > low]
    return area_from_footprints(feet, stature, turn)
