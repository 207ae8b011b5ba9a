"""The time of each segment of a worker's action, from MTM-1 element times (:mod:`ergosim.worker.mtm`).

An action's key poses (:class:`~ergosim.worker.motion.Worker`) split it into ten segments:

======  ==========================================  =============================================
index   segment                                     MTM-1 element
======  ==========================================  =============================================
0, 1    rest -> above the part -> at the part       Reach: case B (a part lying on a table) or
                                                    case A (a part held out at the handover pose)
2       closing the hand on the part                Grasp G1A
3, 4, 5 lift, carry, lower onto the target          Move: case B (to an approximate location: a part
                                                    set down) or C (to an exact location: a part that
                                                    seats in a slot)
6       fitting the part on its target              Position P1 (set down: loose fit) or P2 + AP2
                                                    (seated: close fit, pushed home); a fastener is then
                                                    held and turned for the action's turn time
7       letting go                                  Release RL1
8, 9    retreat -> rest                             Reach case E (hand out of the way)
======  ==========================================  =============================================

The reach, move and return times come from the hand's path length over their segments, measured on the
planned key poses, and are shared among the segments in proportion to their lengths. The times are MTM-1's
standard performance (a trained operator at a normal pace); a subject's ``speed`` divides them.

The body moves with the hand. Where the worker steps, turns or bends the knees on the way to the part, to
the target or back (the key poses' stance), MTM-1's body motions apply: Sidestep SS-C1 for the pelvis's
travel, Turn Body TBC1 for its turn, Bend B and Arise AB when the knees pass :data:`BEND_KNEE_DEG`. A body
motion and the hand motion it goes with are simultaneous, and the longer of the two, the *limiting
motion*, sets the time (MTM-1's rule for simultaneous motions). A part that must turn in the hand on the
way to its target (``regrasp_deg``) adds a Turn T of that angle (simultaneous with the Move, limiting if
longer), and a Regrasp G2 when it turns more than :data:`REGRASP_FROM_DEG`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim.worker.mtm import (
    APPLY_PRESSURE_TMU,
    BODY_TMU,
    GRASP_TMU,
    POSITION_TMU,
    RELEASE_TMU,
    move_tmu,
    reach_tmu,
    sidestep_tmu,
    tmu_to_s,
    turn_body_tmu,
    turn_tmu,
)

__all__ = ["ActionTiming", "action_timing", "LOOSE_FIT", "CLOSE_FIT", "FASTENER_FIT", "N_SEGMENTS",
           "BEND_KNEE_DEG", "REGRASP_FROM_DEG", "body_motion"]

BEND_KNEE_DEG = 30.0
"""Knee flexion [deg] past which the worker is bending (MTM-1 Bend, then Arise); assumed, a visible squat."""
REGRASP_FROM_DEG = 90.0
"""A part turned in the hand by more than this [deg] is regrasped (G2); assumed: a quarter turn is what the
fingers and the wrist give without changing the hold."""

N_SEGMENTS = 10
_REACH, _GRASP, _MOVE, _POSITION, _RELEASE, _RETURN = (0, 1), (2,), (3, 4, 5), (6,), (7,), (8, 9)

LOOSE_FIT, CLOSE_FIT, FASTENER_FIT = "P1SS", "P2SS", "P2S"
"""MTM-1 Position elements: a part set on an area (P1, loose fit), a square profile into its socket (P2,
close fit, semi-symmetric: it goes in four ways), a round fastener (P2, symmetric)."""


@dataclass(frozen=True)
class ActionTiming:
    """Segment durations (10,) [s] at standard performance, and the MTM-1 analysis in its usual notation
    (e.g. ``R31B G1A M28C P2SS AP2 RL1 R16E``; distances in inches)."""

    durations: np.ndarray
    analysis: str

    @property
    def total(self) -> float:
        return float(self.durations.sum())


def _share(total: float, lengths: np.ndarray) -> np.ndarray:
    """``total`` [s] split in proportion to ``lengths`` (equally if they are all zero)."""
    s = float(lengths.sum())
    return np.full(len(lengths), total / len(lengths)) if s <= 0 else total * lengths / s


def body_motion(start: np.ndarray, end: np.ndarray) -> tuple[float, list[str]]:
    """The MTM-1 body motions between two stances (4,) [m, m, deg, deg]: their time [TMU] and their names."""
    step = float(np.hypot(*(end[:2] - start[:2])))
    turn = float(abs(end[2] - start[2]))
    tmu, words = 0.0, []
    if sidestep_tmu(step) > 0:
        tmu += sidestep_tmu(step)
        words.append(f"SS{max(1, int(round(step / 0.0254)))}C1")
    if turn_body_tmu(turn) > 0:
        tmu += turn_body_tmu(turn)
        words.append("TBC1")
    if (start[3] < BEND_KNEE_DEG) != (end[3] < BEND_KNEE_DEG):
        word = "B" if end[3] >= BEND_KNEE_DEG else "AB"
        tmu += BODY_TMU[word]
        words.append(word)
    return tmu, words


def action_timing(hands: np.ndarray, seats: bool, handover: bool = False, turn_time: float = 0.0,
                  stances: np.ndarray | None = None, regrasp_deg: float = 0.0) -> ActionTiming:
    """MTM-1 timing of one action from the acting hand's positions at its 11 key poses, ``hands`` (11, 3)
    [m]: whether the part ``seats`` in a slot (aligned and pushed in) or is set down, whether it is
    ``handover``-ed by a robot, a fastener's ``turn_time`` [s] (> 0: the part is a fastener), the key poses'
    ``stances`` (11, 4) [m, m, deg, deg] (None: standing still) and how far the part turns in the hand,
    ``regrasp_deg``."""
    hands = np.asarray(hands, dtype=float)
    if hands.shape != (N_SEGMENTS + 1, 3):
        raise ValueError(f"expected (11, 3) key-pose hand positions, got {hands.shape}")
    stances = np.zeros((N_SEGMENTS + 1, 4)) if stances is None else np.asarray(stances, dtype=float)
    lengths = np.linalg.norm(np.diff(hands, axis=0), axis=1)
    d = {name: lengths[list(idx)] for name, idx in
         (("reach", _REACH), ("move", _MOVE), ("return", _RETURN))}
    reach_case = "A" if handover else "B"
    move_case = "C" if seats else "B"
    position = (FASTENER_FIT if turn_time > 0 else CLOSE_FIT) if seats else LOOSE_FIT
    body = {name: body_motion(stances[idx[0]], stances[idx[-1] + 1])
            for name, idx in (("reach", _REACH), ("move", _MOVE), ("return", _RETURN))}
    in_hand = turn_tmu(min(regrasp_deg, 180.0)) if regrasp_deg > 0 else 0.0
    regrasp = GRASP_TMU["G2"] if regrasp_deg > REGRASP_FROM_DEG else 0.0
    reach = max(reach_tmu(d["reach"].sum(), reach_case), body["reach"][0])
    move = max(move_tmu(d["move"].sum(), move_case), in_hand, body["move"][0]) + regrasp
    back = max(reach_tmu(d["return"].sum(), "E"), body["return"][0])
    fit = POSITION_TMU[position] + (APPLY_PRESSURE_TMU["AP2"] if seats else 0.0)
    dur = np.zeros(N_SEGMENTS)
    dur[list(_REACH)] = _share(tmu_to_s(reach), d["reach"])
    dur[_GRASP[0]] = tmu_to_s(GRASP_TMU["G1A"])
    dur[list(_MOVE)] = _share(tmu_to_s(move), d["move"])
    dur[_POSITION[0]] = tmu_to_s(fit) + float(turn_time)
    dur[_RELEASE[0]] = tmu_to_s(RELEASE_TMU["RL1"])
    dur[list(_RETURN)] = _share(tmu_to_s(back), d["return"])

    def inch(x: float) -> int:
        return max(1, int(round(x / 0.0254)))

    words = [f"R{inch(d['reach'].sum())}{reach_case}", *body["reach"][1], "G1A",
             f"M{inch(d['move'].sum())}{move_case}", *body["move"][1]]
    if regrasp_deg > 0:
        words.append(f"T{int(round(min(regrasp_deg, 180.0)))}S")
    if regrasp:
        words.append("G2")
    words.append(position)
    if seats:
        words.append("AP2")
    if turn_time > 0:
        words.append(f"hold {turn_time:g} s")
    words += ["RL1", f"R{inch(d['return'].sum())}E", *body["return"][1]]
    return ActionTiming(dur, " ".join(words))
