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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim.worker.mtm import (
    APPLY_PRESSURE_TMU,
    GRASP_TMU,
    POSITION_TMU,
    RELEASE_TMU,
    move_tmu,
    reach_tmu,
    tmu_to_s,
)

__all__ = ["ActionTiming", "action_timing", "LOOSE_FIT", "CLOSE_FIT", "FASTENER_FIT", "N_SEGMENTS"]

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


def action_timing(hands: np.ndarray, seats: bool, handover: bool = False,
                  turn_time: float = 0.0) -> ActionTiming:
    """MTM-1 timing of one action from the acting hand's positions at its 11 key poses, ``hands`` (11, 3)
    [m]: whether the part ``seats`` in a slot (aligned and pushed in) or is set down, whether it is
    ``handover``-ed by a robot, and a fastener's ``turn_time`` [s] (> 0: the part is a fastener)."""
    hands = np.asarray(hands, dtype=float)
    if hands.shape != (N_SEGMENTS + 1, 3):
        raise ValueError(f"expected (11, 3) key-pose hand positions, got {hands.shape}")
    lengths = np.linalg.norm(np.diff(hands, axis=0), axis=1)
    d = {name: lengths[list(idx)] for name, idx in
         (("reach", _REACH), ("move", _MOVE), ("return", _RETURN))}
    reach_case = "A" if handover else "B"
    move_case = "C" if seats else "B"
    position = (FASTENER_FIT if turn_time > 0 else CLOSE_FIT) if seats else LOOSE_FIT
    dur = np.zeros(N_SEGMENTS)
    reach = reach_tmu(d["reach"].sum(), reach_case)
    move = move_tmu(d["move"].sum(), move_case)
    back = reach_tmu(d["return"].sum(), "E")
    fit = POSITION_TMU[position] + (APPLY_PRESSURE_TMU["AP2"] if seats else 0.0)
    dur[list(_REACH)] = _share(tmu_to_s(reach), d["reach"])
    dur[_GRASP[0]] = tmu_to_s(GRASP_TMU["G1A"])
    dur[list(_MOVE)] = _share(tmu_to_s(move), d["move"])
    dur[_POSITION[0]] = tmu_to_s(fit) + float(turn_time)
    dur[_RELEASE[0]] = tmu_to_s(RELEASE_TMU["RL1"])
    dur[list(_RETURN)] = _share(tmu_to_s(back), d["return"])

    def inch(x: float) -> int:
        return max(1, int(round(x / 0.0254)))

    words = [f"R{inch(d['reach'].sum())}{reach_case}", "G1A", f"M{inch(d['move'].sum())}{move_case}",
             position]
    if seats:
        words.append("AP2")
    if turn_time > 0:
        words.append(f"hold {turn_time:g} s")
    words += ["RL1", f"R{inch(d['return'].sum())}E"]
    return ActionTiming(dur, " ".join(words))
