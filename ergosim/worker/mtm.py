"""MTM-1 element times: how long a trained worker takes to reach, grasp, move, position and release.

Methods-Time Measurement (MTM-1) gives the time of each basic hand motion at standard performance, from
tables over the distance moved and the case of the motion. The values here are those of the MTM-1 data
card (MTM Association for Standards and Research; reproduced in Maynard's Industrial Engineering Handbook,
"Methods-Time Measurement"), in TMU: 1 TMU = 1e-5 h = 0.036 s. Distances in the tables are inches; the
functions take metres and interpolate linearly between the tabulated distances (MTM practice rounds up
to the next tabulated distance; interpolation keeps durations continuous in the geometry, so moving a part
by a centimetre moves the time by a little, not by a table step). Beyond 30 in each table continues with
its published increment per inch.

Cases used by the twin (the worker's key poses, :mod:`ergosim.worker.motion`):

- Reach, case A: to an object in a fixed location or in the other hand, here one held out by the robot at
  the pre-planned handover pose; case B: to a single object whose location varies slightly from cycle to
  cycle (a part lying on a table); case E: to an indefinite location, to get the hand out of the way (the
  return to rest).
- Move, case B: to an approximate location (setting a part down); case C: to an exact location (bringing a
  profile to the hollow it is inserted into).
- Grasp G1A: pick-up grasp of an object lying by itself, easily grasped.
- Position P1: loose fit, no pressure (a part set onto a marked area); P2: close fit, light pressure (a 30 mm
  profile into its socket, 0.5 mm clearance). S symmetric, SS semi-symmetric (a square profile fits four
  ways), NS non-symmetric.
- Apply pressure AP2 (without regrasp): pushing a profile home in its socket.
- Release RL1: normal release by opening the fingers.
- Turn: rotation of the hand about the forearm axis (a screw turned with the fingers, a profile turned
  upright in the hand); Regrasp G2: the part changes its hold in the fingers.
- Body motions (Table X): Sidestep, case 1 (complete when the leading leg contacts the floor): under 12 in it
  takes no time of its own ("use Reach or Move time"), from 12 in 17.0 TMU plus 0.6 per further inch;
  Turn Body, case 1, 45-90 deg: 18.6 TMU; Bend (B) 29.0 TMU and Arise (AB) 31.9 TMU.
"""

from __future__ import annotations

import numpy as np

from ergosim.errors import ConfigError

__all__ = ["TMU_S", "INCH_M", "reach_tmu", "move_tmu", "GRASP_TMU", "POSITION_TMU", "APPLY_PRESSURE_TMU",
           "RELEASE_TMU", "turn_tmu", "tmu_to_s", "BODY_TMU", "sidestep_tmu", "turn_body_tmu"]

TMU_S = 0.036
"""One time-measurement unit [s] (1e-5 h; MTM-1 data card)."""
INCH_M = 0.0254

_DIST_IN = np.array([0.75, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30],
                    dtype=float)
# MTM-1 data card, Table I (Reach, R): TMU per distance [in], cases A, B, C or D, E.
_REACH = {
    "A": [2.0, 2.5, 4.0, 5.3, 6.1, 6.5, 7.0, 7.4, 7.9, 8.3, 8.7,
          9.6, 10.5, 11.4, 12.3, 13.1, 14.0, 14.9, 15.8, 16.7, 17.5],
    "B": [2.0, 2.5, 4.0, 5.3, 6.4, 7.8, 8.6, 9.3, 10.1, 10.8, 11.5,
          12.9, 14.4, 15.8, 17.2, 18.6, 20.1, 21.5, 22.9, 24.4, 25.8],
    "C": [2.0, 3.6, 5.9, 7.3, 8.4, 9.4, 10.1, 10.8, 11.5, 12.2, 12.9,
          14.2, 15.6, 17.0, 18.4, 19.8, 21.2, 22.5, 23.9, 25.3, 26.7],
    "E": [2.0, 2.4, 3.8, 5.3, 6.8, 7.4, 8.0, 8.7, 9.3, 9.9, 10.5,
          11.8, 13.0, 14.2, 15.5, 16.7, 18.0, 19.2, 20.4, 21.7, 22.9],
}
_REACH_PER_IN = {"A": 0.4, "B": 0.7, "C": 0.7, "E": 0.6}
"""Table I, "additional TMU per inch over 30 inches"."""
# MTM-1 data card, Table II (Move, M), weight up to 2.5 lb (no weight allowance): cases A, B, C.
_MOVE = {
    "A": [2.0, 2.5, 3.6, 4.9, 6.1, 7.3, 8.1, 8.9, 9.7, 10.5, 11.3,
          12.9, 14.4, 16.0, 17.6, 19.2, 20.8, 22.4, 24.0, 25.5, 27.1],
    "B": [2.0, 2.9, 4.6, 5.7, 6.9, 8.0, 8.9, 9.7, 10.6, 11.5, 12.2,
          13.4, 14.6, 15.8, 17.0, 18.2, 19.4, 20.6, 21.8, 23.1, 24.3],
    "C": [2.0, 3.4, 5.2, 6.7, 8.0, 9.2, 10.3, 11.1, 11.8, 12.7, 13.5,
          15.2, 16.9, 18.7, 20.4, 22.1, 23.8, 25.5, 27.3, 29.0, 30.7],
}
_MOVE_PER_IN = {"A": 0.8, "B": 0.6, "C": 0.85}

GRASP_TMU = {"G1A": 2.0, "G1B": 3.5, "G1C1": 7.3, "G2": 5.6, "G3": 5.6, "G4A": 7.3, "G5": 0.0}
"""Table IV (Grasp): G1A small, medium or large object by itself, easily grasped; G3 transfer grasp."""
POSITION_TMU = {"P1S": 5.6, "P1SS": 9.1, "P1NS": 10.4, "P2S": 16.2, "P2SS": 19.7, "P2NS": 21.0,
                "P3S": 43.0, "P3SS": 46.5, "P3NS": 47.8}
"""Table V (Position), parts easy to handle: class of fit 1 loose, 2 close, 3 exact; symmetry S, SS, NS."""
APPLY_PRESSURE_TMU = {"AP1": 16.2, "AP2": 10.6}
"""Table IX (Apply pressure): AP2 without regrasp, AP1 with."""
RELEASE_TMU = {"RL1": 2.0, "RL2": 0.0}
"""Table VI (Release): RL1 normal release by opening the fingers; RL2 contact release."""
_TURN_DEG = np.array([30, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180], dtype=float)
_TURN_SMALL = [2.8, 3.5, 4.1, 4.8, 5.4, 6.1, 6.8, 7.4, 8.1, 8.7, 9.4]
"""Table III (Turn), weight small (0-2 lb): TMU per degrees turned."""


BODY_TMU = {"SS-C1": 17.0, "TBC1": 18.6, "B": 29.0, "AB": 31.9}
"""Table X (Body, leg and foot motions): Sidestep case 1 at 12 in, Turn Body case 1 (45-90 deg), Bend,
Arise."""
_SIDESTEP_FROM_IN, _SIDESTEP_PER_IN = 12.0, 0.6


def sidestep_tmu(distance_m: float) -> float:
    """Sidestep, case 1, of ``distance_m`` [m] [TMU]: 0 under 12 in (the step goes with the hand's Reach or
    Move), else 17.0 TMU at 12 in plus 0.6 TMU per further inch."""
    d_in = max(float(distance_m), 0.0) / INCH_M
    if d_in < _SIDESTEP_FROM_IN - 1e-9:
        return 0.0
    return BODY_TMU["SS-C1"] + _SIDESTEP_PER_IN * (d_in - _SIDESTEP_FROM_IN)


def turn_body_tmu(degrees: float) -> float:
    """Turn Body, case 1, through ``degrees`` [TMU]: none under 45 deg, one TBC1 (18.6 TMU) per 90 deg
    started from 45 deg."""
    deg = abs(float(degrees))
    return 0.0 if deg < 45.0 else BODY_TMU["TBC1"] * float(np.ceil(deg / 90.0))


def tmu_to_s(tmu: float) -> float:
    """``tmu`` time-measurement units in seconds."""
    return float(tmu) * TMU_S


def _table(distance_m: float, table: dict, per_in: dict, case: str, what: str) -> float:
    if case not in table:
        raise ConfigError(f"unknown MTM-1 {what} case {case!r}; cases: {', '.join(table)}", where="mtm")
    d_in = max(float(distance_m), 0.0) / INCH_M
    if d_in <= _DIST_IN[0]:
        return table[case][0]
    if d_in <= _DIST_IN[-1]:
        return float(np.interp(d_in, _DIST_IN, table[case]))
    return table[case][-1] + per_in[case] * (d_in - _DIST_IN[-1])


def reach_tmu(distance_m: float, case: str = "B") -> float:
    """Reach R of ``distance_m`` [m] in MTM-1 case A, B, C or E [TMU]; 3/4 in or less counts as 3/4 in."""
    return _table(distance_m, _REACH, _REACH_PER_IN, case, "reach")


def move_tmu(distance_m: float, case: str = "B") -> float:
    """Move M of ``distance_m`` [m] in MTM-1 case A, B or C, for parts under 2.5 lb (1.1 kg) [TMU]."""
    return _table(distance_m, _MOVE, _MOVE_PER_IN, case, "move")


def turn_tmu(degrees: float) -> float:
    """Turn T of ``degrees`` (30..180; more is several turns) of a light object [TMU]."""
    deg = abs(float(degrees))
    full, rest = divmod(deg, 180.0)
    tmu = full * _TURN_SMALL[-1]
    if rest > 0:
        tmu += float(np.interp(max(rest, 30.0), _TURN_DEG, _TURN_SMALL))
    return tmu
