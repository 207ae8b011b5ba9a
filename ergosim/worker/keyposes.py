"""The key poses of one action: whole bodies at the part and at the target, from the whole-body IK.

An action passes through eleven key bodies (:data:`KEY_NAMES`): rest, above the part, at the part (held
while the hand closes), lifted (looking at the target), above the target, at the target (held while the
part is fitted and let go), retreated, rest. The stance is chosen first, once at the part and once at the
target (:func:`ergosim.worker.stance.choose_stance`), and the IK solves the body for it; the worker keeps
that stance for the approach and the retreat (people do not step during a final approach): the step and
the turn happen while the hand travels, rest -> part and part -> target, and back home on the return. A
target below the knee is reached squatting (:func:`ergosim.worker.ik_prior.squat_prior`).

The hand keeps its grip's orientation at the target (a 6-D solve) unless turning the part in the hand
spares the worker more than :data:`REGRASP_COST`, or keeping it is out of reach (a profile lying flat on
a table, to be stood upright in a hollow): the part is then reoriented in the hand on the way (MTM-1
Turn, and a Regrasp past 90 deg, :mod:`ergosim.worker.action_timing`), the place pose is a position-only
solve and ``regrasp_deg`` is the rotation the fingers give the part.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.ik import IKSolution, WholeBodyIK, log_so3
from ergosim.worker.ik_prior import IKPrior, squat_prior
from ergosim.worker.stance import StanceRule, StandingArea, choose_stance

__all__ = ["KEY_NAMES", "KeyPoses", "plan_keyposes", "approach_point"]

KEY_NAMES = ("rest", "above_part", "at_part", "grasped", "lifted", "above_target", "at_target", "fitted",
             "released", "retreated", "back")
APPROACH_UP = 0.06
"""m above the part or target before the final approach (assumed)."""
APPROACH_BACK = 0.04
"""m towards the acting shoulder before the final approach (assumed)."""
REGRASP_COST = 1.0
"""Posture cost (units of one neutral-zone edge, :mod:`ergosim.worker.ik_prior`) a worker accepts to keep
the grip rather than turn the part in the hand (assumed: one unit)."""
PLACE_TOL = 0.005
"""m: a keep-the-grip place pose worse than this falls back to position-only with a regrasp."""


@dataclass(frozen=True)
class KeyPoses:
    """(11, 27) key bodies [deg, m] (:data:`KEY_NAMES`), the IK residuals at the part and at the target,
    and ``regrasp_deg``: how far the part turns in the hand between grasp and place (0 with the grip kept)."""

    bodies: np.ndarray
    reach_error: float
    place_error: float
    place_rot_error_deg: float
    regrasp_deg: float


STRAIGHT_IN = (0.12, 10.0)
"""A part this close to its target [m] and turned this little from it [deg] (a robot presenting it at the
target, :data:`ergosim.scenes.cellbuild.PRESENT_STANDOFF`) is pushed straight in."""


def _on_its_way_in(part: tuple[np.ndarray, np.ndarray], target: tuple[np.ndarray, np.ndarray]) -> bool:
    (p, r), (t, rt) = part, target
    turn = float(np.rad2deg(np.linalg.norm(log_so3(rt @ r.T))))
    return float(np.linalg.norm(p - t)) <= STRAIGHT_IN[0] and turn <= STRAIGHT_IN[1]


def approach_point(ik: WholeBodyIK, point: np.ndarray, body: np.ndarray, shoulder: str) -> np.ndarray:
    """A point :data:`APPROACH_UP` above ``point`` and :data:`APPROACH_BACK` towards the acting shoulder of
    ``body`` (the approach and retreat waypoint)."""
    back = ik.point(body, shoulder)[:2] - point[:2]
    back = back / max(np.linalg.norm(back), 1e-9)
    return point + np.array([*(APPROACH_BACK * back), APPROACH_UP])


_N = len(HUMAN_JOINTS)
_KNEE, _ANKLE = _N + 3, _N + 4


def stance_at(rest: np.ndarray, point: np.ndarray, rule: StanceRule, area: StandingArea,
              prior: IKPrior) -> tuple[np.ndarray, IKPrior]:
    """The start of the solves at ``point``: the body ``rest`` (27,) moved to the chosen stance, the legs
    straight or, where the worker squats, already bent; and the prior for that reach."""
    start = np.array(rest, dtype=float)
    start[_N:_N + 3] = choose_stance(point, rule, area)
    if point[2] < rule.knee_height:
        squat = squat_prior(prior)
        start[_KNEE], start[_ANKLE] = squat.pref[_KNEE], squat.pref[_ANKLE]
        return start, squat
    start[_KNEE] = start[_ANKLE] = 0.0
    return start, prior


BACK_OFF = 0.08
"""m a stance steps back towards the spot when the body cannot reach from it without passing through the
furniture (a squatting worker's knees against a bin; assumed: a short shuffle)."""
MAX_BACK_OFFS = 3


def _clear_of_the_furniture(ik: WholeBodyIK, start: np.ndarray, solve) -> IKSolution:
    """``solve(start)``; where that posture passes through the furniture, the stance backs off towards the
    spot by :data:`BACK_OFF` (at most :data:`MAX_BACK_OFFS` times) and the clearest solution is kept: the
    stance is chosen among candidates, the first clear one winning."""
    best = solve(start)
    if not ik.obstacles or ik.clearance() >= 0.0:
        return best
    best_clear = ik.clearance()
    step = start[_N:_N + 2]
    length = float(np.linalg.norm(step))
    for k in range(1, MAX_BACK_OFFS + 1):
        if length <= 0.0:
            break
        candidate = start.copy()
        candidate[_N:_N + 2] = step * max(0.0, 1.0 - k * BACK_OFF / length)
        sol = solve(candidate)
        clear = ik.clearance()
        if clear > best_clear:
            best, best_clear = sol, clear
        if clear >= 0.0 or not candidate[_N:_N + 2].any():
            break
    return best


def plan_keyposes(ik: WholeBodyIK, rest: np.ndarray, part: tuple[np.ndarray, np.ndarray],
                  target: tuple[np.ndarray, np.ndarray], prior: IKPrior, area: StandingArea,
                  side: str, rule: StanceRule, grip: np.ndarray | None = None) -> KeyPoses:
    """Key bodies for moving a part at ``part`` (position (3,), rotation (3, 3)) onto ``target`` (the same),
    both in the IK model's frame, starting and ending at ``rest`` (27,). ``grip`` (3,): where the hand takes
    the part, in the part's frame (None: its origin)."""
    part_pos, part_rot = part
    tgt_pos, tgt_rot = target
    grip = np.zeros(3) if grip is None else np.asarray(grip, dtype=float)
    grip_pos = part_pos + part_rot @ grip  # where the hand closes
    grip_tgt = tgt_pos + tgt_rot @ grip  # where that point of the part ends
    shoulder = ik.model.body(ik.human.shoulder_body[side]).name
    at_part, part_prior = stance_at(rest, grip_pos, rule, area, prior)

    def solve(q0: np.ndarray, point: np.ndarray, look: np.ndarray, rot: np.ndarray | None = None,
              pr: IKPrior = part_prior, max_iter: int | None = None) -> IKSolution:
        return ik.solve(q0, point, side, target_rot=rot, gaze=look, prior=pr, max_iter=max_iter)

    grasp = _clear_of_the_furniture(ik, at_part, lambda q0: solve(q0, grip_pos, grip_pos))
    above_part = approach_point(ik, grip_pos, grasp.body, shoulder)
    lift = solve(grasp.body, above_part, grip_pos)
    straight_in = _on_its_way_in(part, target)
    if straight_in:  # held out aligned with its target: pushed straight in, no lift
        lifted = solve(grasp.body, grip_pos, tgt_pos)
    else:
        lifted = solve(lift.body, above_part, tgt_pos)  # the hand stays, the head turns to the target
    hand_p, hand_r = ik.hand_pose(grasp.body, side)
    part_in_hand = hand_r.T @ (part_pos - hand_p)
    rot_in_hand = hand_r.T @ part_rot
    # where the hand must be for the part to sit on the target, keeping the grip
    place_rot = tgt_rot @ rot_in_hand.T
    place_pos = tgt_pos - place_rot @ part_in_hand
    if straight_in:  # pushed home from where it was taken: no step between
        at_target, tgt_prior = lifted.body, part_prior
    else:
        at_target, tgt_prior = stance_at(lifted.body, grip_tgt, rule, area, prior)
    kept = _clear_of_the_furniture(
        ik, at_target, lambda q0: solve(q0, place_pos, tgt_pos, place_rot, tgt_prior, max_iter=40))
    turned = _clear_of_the_furniture(ik, at_target, lambda q0: solve(q0, grip_tgt, tgt_pos, pr=tgt_prior))
    _, hand_r5 = ik.hand_pose(turned.body, side)
    turn_deg = float(np.rad2deg(np.linalg.norm(log_so3(tgt_rot @ (hand_r5 @ rot_in_hand).T))))
    # the worker keeps the grip unless turning the part in the hand spares more than a neutral zone's worth
    keep_grip = kept.pos_error <= PLACE_TOL and kept.cost <= turned.cost + REGRASP_COST
    place, regrasp = (kept, 0.0) if keep_grip else (turned._replace(rot_error_deg=turn_deg), turn_deg)
    above_tgt = approach_point(ik, place_pos if keep_grip else grip_tgt, place.body, shoulder)
    retreat = solve(place.body, above_tgt, tgt_pos, pr=tgt_prior)
    down = retreat
    if straight_in and keep_grip:
        down = lifted
    elif keep_grip:  # lowering onto the target keeps the grip's orientation where that converges quickly
        keep = solve(place.body, above_tgt, tgt_pos, place_rot, tgt_prior, max_iter=25)
        if keep.pos_error <= PLACE_TOL:
            down = keep
    b = [rest, lift.body, grasp.body, grasp.body, lifted.body, down.body, place.body, place.body,
         place.body, retreat.body, rest]
    return KeyPoses(np.array(b), grasp.pos_error, place.pos_error, place.rot_error_deg, regrasp)
