"""How much a hand-over spares the worker: its part of a hand-over against doing the action alone (issue 23).

A robot doing a §7.2 action presents the part at its target (docs/fidelity.md, "Hand-overs that spare the
worker"); the worker reaches for it, takes it and pushes it home. This module plans both executions for
the scenario's subjects, from the same scene state (J at the assembly area for a2-a4), and compares the
integral of the five KWear joint scores over each, ∫ Σ_i G_i dt (paper eq. 3), and the wear it predicts,
Σ_i (1 - α_i) with α_i = exp(-∫ G_i dt / C) (eq. 9). No noise and no variability: the nominal postures
and the MTM-1 times at the subject's pace.

    python -m ergosim.fidelity.handover_wear [--subjects 12] [--seed 0]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from collections.abc import Sequence

import numpy as np

from ergosim.ergonomics.kwear import KWearParams, alpha_of
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell
from ergosim.twin.calibration import put_part
from ergosim.worker import Worker, score_frames

__all__ = ["Wear", "measure"]

ACTIONS = ("a1", "a2", "a3", "a4")


@dataclasses.dataclass(frozen=True)
class Wear:
    """One execution: ``score_integral`` ∫ Σ G dt [score·s], ``alpha_loss`` Σ (1 - α), ``duration`` [s]."""

    score_integral: float
    alpha_loss: float
    duration: float


def _wear(motion, params: KWearParams) -> Wear:
    _, _, g = score_frames(motion.angles)
    dt = np.diff(motion.t, prepend=0.0)
    integral = float(np.nansum(g * dt[:, None]))
    return Wear(integral, float(np.sum(1.0 - alpha_of(g, dt, params))), motion.duration)


def measure(scenario: str = "multi-subject", subjects: int = 12, seed: int = 0,
            actions: Sequence[str] = ACTIONS) -> dict[str, list[tuple[Wear, Wear]]]:
    """action -> one (alone, hand-over) pair per subject of ``seed``'s population."""
    sc = load_scenario(scenario)
    params = KWearParams()
    out: dict[str, list[tuple[Wear, Wear]]] = {a: [] for a in actions}
    for index in range(subjects):
        subject = scenario_subject(sc, index, seed)
        subject = dataclasses.replace(subject, variability_deg=0.0, timing_variability=0.0)
        for action in actions:
            cell = subject_cell(sc, subject)
            worker = Worker(dataclasses.replace(subject, handedness=cell.config.worker.hand))
            rng = np.random.default_rng([seed, index])
            g = cell.actions[action]
            first = cell.actions[ACTIONS[0]]
            if action != ACTIONS[0]:  # J already at the assembly area
                put_part(cell, first.part, *cell.site_pose(first.target))
            alone = worker.plan(cell, g, rng, action=action)
            put_part(cell, g.part, *cell.site_pose(g.handover))
            handed = worker.plan(cell, g, rng, action=action, handover=True)
            out[action].append((_wear(alone, params), _wear(handed, params)))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="multi-subject")
    parser.add_argument("--subjects", type=int, default=12)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    print("| action | ∫ΣG alone | ∫ΣG hand-over | ratio (range) | Σ(1 − α) alone / hand-over | "
          "duration alone / hand-over [s] |")
    print("|---|---|---|---|---|---|")
    for action, pairs in measure(args.scenario, args.subjects, args.seed).items():
        alone = np.array([[a.score_integral, a.alpha_loss, a.duration] for a, _ in pairs])
        handed = np.array([[h.score_integral, h.alpha_loss, h.duration] for _, h in pairs])
        ratio = handed[:, 0] / alone[:, 0]
        a, h = alone.mean(axis=0), handed.mean(axis=0)
        spread = f"{ratio.mean():.2f} ({ratio.min():.2f}–{ratio.max():.2f})"
        print(f"| {action} | {a[0]:.1f} | {h[0]:.1f} | {spread} | {a[1]:.2f} / {h[1]:.2f} "
              f"| {a[2]:.1f} / {h[2]:.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
