"""Calibrating the workers' pace against the timing facts of §7.1 and §7.2.

Both experiments' pace is the geometric middle of the band of paces that the paper's facts allow.

§7.1.
§7.1 gives no durations. Its Table 1 does say when the subject's wear first reached V_th = 0.8: at the
start of rp2 (rp1 all H, a1 of rp2 by the robot). With the paper's KWear constants (eq. 6-7) that fixes how
long the subject spent in her postures per action: at MTM-1 standard pace (a trained operator in practised
short-cycle work, :mod:`ergosim.worker.action_timing`) one repetition builds far too little wear, so the
validation subject worked more slowly than MTM-1's standard, as a single lab subject holding postures near
the end of their range of motion would.

:func:`pace_scan` runs the §7.1 scenario (KWear mode, two repetitions) at a grid of paces and records, per
seed, the repetition of the first robot decision. The calibrated pace is the middle (geometric mean) of the
interval where most seeds first call the robot in rp2: the centre of the band that the fact allows, not an
edge of it. Only this first crossing is calibrated; which actions go to the robot in rp2-rp4, and how many,
are left to the simulation and checked by the fidelity report.

§7.2. "In H only ... when the human finished the repetition, he had to wait until T_takt passed": every
subject's H-only repetition fitted in the takt. Durations scale as 1 / pace, so the slowest H-only repetition
at MTM-1 standard pace, T_1, bounds the pace from below: pace >= T_1 / T_takt. MTM-1's standard is a
practised operator's, which naive subjects do not beat: pace <= 1. :func:`h_only_band` measures T_1 over
the subjects of the given seeds; the calibrated pace is sqrt(T_1 / T_takt).
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.scenario_run import run_scenario
from ergosim.fidelity.checks import table1_of

__all__ = ["PaceRow", "first_robot_repetition", "pace_scan", "calibrated_pace", "h_only_band"]


@dataclasses.dataclass(frozen=True)
class PaceRow:
    pace: float
    first_robot: dict[int, int | None]
    """seed -> the repetition (1-based) of the first robot decision, None if the robot was never chosen."""


def first_robot_repetition(summary: dict) -> int | None:
    for rep, row in enumerate(table1_of(summary, "hrc"), start=1):
        if "R" in row:
            return rep
    return None


def pace_scan(paces: Sequence[float], seeds: Sequence[int], scenario: str = "kwear-validation",
              repetitions: int = 2, log: Callable[[str], None] = lambda _msg: None) -> list[PaceRow]:
    rows = []
    for pace in paces:
        first = {}
        for seed in seeds:
            over = {"pace": repr(pace), "modes": "hrc", "repetitions": str(repetitions)}
            sc = load_scenario(scenario, over)
            with tempfile.TemporaryDirectory() as tmp:
                result = run_scenario(sc, seed=seed, out=Path(tmp) / "run", jobs=1, progress=False,
                                      plots=False)
                first[seed] = first_robot_repetition(result.summary)
        log(f"pace {pace:.3f}: first robot decision in rp {first}")
        rows.append(PaceRow(pace, first))
    return rows


def calibrated_pace(rows: Sequence[PaceRow], target_rep: int = 2) -> float | None:
    """The geometric middle of the paces at which most seeds first call the robot in ``target_rep``."""
    ok = [r.pace for r in rows
          if sum(v == target_rep for v in r.first_robot.values()) > len(r.first_robot) / 2]
    if not ok:
        return None
    return math.sqrt(min(ok) * max(ok))


def h_only_band(seeds: Sequence[int], scenario: str = "multi-subject",
                log: Callable[[str], None] = lambda _msg: None) -> tuple[float, float, float]:
    """(lowest pace, highest pace, calibrated pace) that §7.2's H-only fact allows: one H-only repetition of
    every subject of ``seeds`` at MTM-1 standard pace; the slowest, T_1, over the takt is the lowest pace."""
    slowest = 0.0
    takt = load_scenario(scenario).protocol.pacing.takt
    for seed in seeds:
        sc = load_scenario(scenario, {"pace": "1.0", "modes": "h-only", "repetitions": "1"})
        with tempfile.TemporaryDirectory() as tmp:
            result = run_scenario(sc, seed=seed, out=Path(tmp) / "run", jobs=None, progress=False,
                                  plots=False)
        reps = [r["duration_s"] for r in result.summary["modes"]["h-only"]["repetitions"]
                if r["duration_s"] is not None]
        log(f"seed {seed}: H-only repetitions at MTM-1 standard pace take {min(reps):.1f}-{max(reps):.1f} s")
        slowest = max(slowest, *reps)
    low = slowest / takt
    return low, 1.0, math.sqrt(low * 1.0)
