"""How the worker's assumed stance and balance constants move its postures: one constant at a time.

    python scripts/worker_sensitivity.py [--seed 0]

Plans §7.2's a2 (L, the piece beyond reach on the side table) and a1 (J) and the user's low-bin reach
(examples/pcb_enclosure p1) for subject 0 of ``--seed``, at each constant's default and at a lower and a
higher value, and prints a markdown table: the longest step [m], the deepest knee flexion [deg], the mean
RULA upper-arm and trunk scores while reaching and taking the part, the mean grand score, the action's
duration [s] and the smallest balance margin [m]. The constants (``ergosim.worker.stance``,
``ergosim.worker.ik``, ``ergosim.worker.ik_prior``) are set on their modules for the plan and restored.
"""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path

import numpy as np

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell
from ergosim.worker import Worker, ik_prior, score_frames, stance
from ergosim.worker import ik as ik_module

PCB = Path(__file__).resolve().parents[1] / "examples" / "pcb_enclosure" / "pcb.toml"
CASES = (("multi-subject", "a1"), ("multi-subject", "a2"), (str(PCB), "p1"))
CONSTANTS = {  # module, name, (low, default, high)
    "STEP_FROM_REACH": (stance, "STEP_FROM_REACH", (0.8, 1.0, 1.2)),
    "WORK_REACH": (stance, "WORK_REACH", (0.55, 0.7, 0.85)),
    "TURN_FROM_DEG": (stance, "TURN_FROM_DEG", (30.0, 45.0, 60.0)),
    "COM_SIGMA": (ik_module, "COM_SIGMA", (0.025, 0.05, 0.1)),
    "SQUAT_KNEE_DEG": (ik_prior, "SQUAT_KNEE_DEG", (45.0, 60.0, 90.0)),
}


@contextlib.contextmanager
def _set(module, name: str, value: float):
    old = getattr(module, name)
    setattr(module, name, value)
    try:
        yield
    finally:
        setattr(module, name, old)


def _row(scenario_name: str, action: str, seed: int) -> tuple:
    scenario = load_scenario(scenario_name)
    subject = scenario_subject(scenario, 0, seed)
    cell = subject_cell(scenario, subject)
    worker = Worker(subject)
    m = worker.plan(cell, cell.actions[action], np.random.default_rng(seed), action=action)
    parts, grand, _ = score_frames(m.angles)
    take = m.t <= m.phases[1].end
    ua, tr = RULA_PARTS.index("upper_arm"), RULA_PARTS.index("trunk")
    return (float(np.hypot(m.stances[:, 0], m.stances[:, 1]).max()), float(m.stances[:, 3].max()),
            float(parts[take, ua].mean()), float(parts[take, tr].mean()), float(grand.mean()), m.duration,
            float(m.balance.min()))


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seed", type=int, default=0)
    a = p.parse_args()
    print("| constant | value | action | step [m] | knees [°] | upper arm | trunk | grand | duration [s] | "
          "balance [m] |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for label, (module, name, values) in CONSTANTS.items():
        for value in values:
            with _set(module, name, value):
                for scenario_name, action in CASES:
                    r = _row(scenario_name, action, a.seed)
                    mark = " (default)" if value == values[1] else ""
                    print(f"| {label} | {value:g}{mark} | {Path(scenario_name).stem} {action} | {r[0]:.2f} | "
                          f"{r[1]:.0f} | {r[2]:.2f} | {r[3]:.2f} | {r[4]:.2f} | {r[5]:.1f} | {r[6]:.3f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
