"""How the simulated worker stood and moved in a run: the figures an ergonomist checks first.

Read from a run folder's ``ticks.csv`` (the true stance, the measured angles, the balance margin and the
clearance of every 20 Hz tick) and ``allocations.csv`` (which action the worker did when), per action of
the worker's:

- ``neck_at_limit``: the share of acting ticks whose neck flexion is within 3 deg of the model's 45 deg
  limit (the measured angle, as the suit reports it);
- ``behind_spot``: the share of acting ticks whose stance stands more than 3 cm behind the worker's spot;
- ``step``: the longest step from the spot [m] (the stance's pelvis_x, pelvis_y);
- ``knee``: the deepest knee flexion [deg];
- ``com_margin``: the smallest margin of the centre of mass inside the base of support [m] (every tick,
  acting or resting);
- ``clearance``: the smallest clearance of the body from the furniture [m] (NaN without furniture).

:func:`posture_figures` returns them for the whole run and per action; :func:`action_wear` gives the
per-action RULA grand score G(a_k) under the twin's rule (the worst posture held 1 s,
:mod:`ergosim.ergonomics.rula_action`) over all the action's executions, and the KWear wear per execution
(the sum over the five joints of V at the end of the action less V at its start, paper eqs. 3-5).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ergosim.ergonomics.rula_action import action_grand_score
from ergosim.posture import KWEAR_JOINTS

__all__ = ["PostureFigures", "posture_figures", "action_wear", "NECK_LIMIT_DEG", "NEAR_LIMIT_DEG"]

NECK_LIMIT_DEG = 45.0
"""The human model's neck flexion limit (AAOS, :mod:`ergosim.human.joints`)."""
NEAR_LIMIT_DEG = 3.0
BEHIND = 0.03  # m


@dataclass(frozen=True)
class PostureFigures:
    """The figures of the module docstring over a set of ticks."""

    acting_ticks: int
    neck_at_limit: float
    behind_spot: float
    step: float
    knee: float
    com_margin: float
    clearance: float


def _table(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    out = {}
    for k, name in enumerate(head):
        col = [r[k] for r in body]
        try:
            out[name] = np.array([float(v) if v != "" else np.nan for v in col])
        except ValueError:
            out[name] = np.array(col)
    return out


def _figures(t: dict[str, np.ndarray], rows: np.ndarray, acting: np.ndarray) -> PostureFigures:
    act = rows & acting
    n = int(act.sum())
    neck = t["neck_flexion"][act]
    neck = neck[np.isfinite(neck)]
    step = np.hypot(t["pelvis_x"][act], t["pelvis_y"][act])
    clear = t["clearance"][rows]
    return PostureFigures(
        acting_ticks=n,
        neck_at_limit=float((neck >= NECK_LIMIT_DEG - NEAR_LIMIT_DEG).mean()) if neck.size else 0.0,
        behind_spot=float((t["pelvis_x"][act] < -BEHIND).mean()) if n else 0.0,
        step=float(step.max()) if n else 0.0,
        knee=float(t["knee_flexion"][act].max()) if n else 0.0,
        com_margin=float(np.nanmin(t["com_margin"][rows])) if rows.any() else float("nan"),
        clearance=float(np.nanmin(clear)) if np.isfinite(clear).any() else float("nan"),
    )


def _action_of_ticks(t: dict[str, np.ndarray], alloc: dict[str, np.ndarray]) -> np.ndarray:
    """The action each tick belongs to ("" outside the worker's actions)."""
    label = np.full(len(t["t"]), "", dtype=object)
    human = (alloc["agent"] == "human") & (alloc["status"] == "done")
    for k in np.flatnonzero(human):
        rows = ((t["subject"] == alloc["subject"][k]) & (t["mode"] == alloc["mode"][k])
                & (t["repetition"] == alloc["repetition"][k]) & (t["t"] > alloc["t_start"][k])
                & (t["t"] <= alloc["t_end"][k] + 1e-9))
        label[rows] = alloc["action"][k]
    return label


def posture_figures(run_dir: str | Path, subject: int | None = None) -> dict[str, PostureFigures]:
    """The figures for the whole run (key ``"all"``) and per action of the worker's (keys the labels), over
    every subject or one."""
    run_dir = Path(run_dir)
    t = _table(run_dir / "ticks.csv")
    alloc = _table(run_dir / "allocations.csv")
    acting = t["acting"] == 1
    labels = _action_of_ticks(t, alloc)
    mine = np.ones(len(labels), dtype=bool) if subject is None else t["subject"] == subject
    out = {"all": _figures(t, mine, acting)}
    for action in sorted(set(labels[mine]) - {""}):
        out[action] = _figures(t, mine & (labels == action), acting)
    return out


def action_wear(run_dir: str | Path) -> dict[str, tuple[float, float, int]]:
    """Per action of the worker's: (G(a_k) over its executions, mean KWear wear per execution ΣΔV over the
    five joints, executions)."""
    run_dir = Path(run_dir)
    t = _table(run_dir / "ticks.csv")
    alloc = _table(run_dir / "allocations.csv")
    v = np.column_stack([t[f"kwear_{j}"] for j in KWEAR_JOINTS]).sum(axis=1)
    out: dict[str, list] = {}
    human = np.flatnonzero((alloc["agent"] == "human") & (alloc["status"] == "done"))
    for k in human:
        run = (t["subject"] == alloc["subject"][k]) & (t["mode"] == alloc["mode"][k])
        same = run & (t["repetition"] == alloc["repetition"][k])
        inside = same & (t["t"] > alloc["t_start"][k]) & (t["t"] <= alloc["t_end"][k] + 1e-9)
        before = run & (t["t"] <= alloc["t_start"][k] + 1e-9)  # V carries over from the repetition before
        if not inside.any():
            continue
        v0 = v[before][-1] if before.any() else 0.0
        wear = float(v[inside][-1] - v0)
        out.setdefault(str(alloc["action"][k]), []).append((t["rula_grand"][inside], wear))
    return {a: (float(action_grand_score([x[0] for x in r])), float(np.mean([x[1] for x in r])), len(r))
            for a, r in out.items()}
