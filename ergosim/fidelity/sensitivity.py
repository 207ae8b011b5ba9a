"""Sensitivity of the fidelity figures to the calibrated parameters (issue 13, "not a knife edge").

Each calibrated parameter is moved by a factor (0.9 and 1.1 by default) and both experiments are run again
with everything else as calibrated. The parameters, as ``--set`` overrides of the paper scenarios:

- ``shelf_height``: §7.1's top ledge (where J starts);
- ``piece_distance``: every piece's initial position and every place target, moved that many times as far
  from the worker in both cells (kept on the surface it lies on);
- ``pace``: the subjects' mean pace (MTM-1 performance);
- ``transit_speed``: the robot's free-space speed.

A row per (parameter, factor) gives the figures that make the paper's shape: §7.1 seeds holding Table 1's
shape, §7.2 robot share overall and per action, HRC overruns, the mean HRC repetition and the robot-only
assembly time.
"""

from __future__ import annotations

import dataclasses
import statistics
from collections.abc import Callable
from pathlib import Path

from ergosim.experiment.scenario import load_scenario
from ergosim.fidelity.checks import Bounds, fidelity_rows, robot_only_time
from ergosim.fidelity.experiments import Plan, Runs, run_experiments
from ergosim.scenes import parse_cell

__all__ = ["PARAMETERS", "SensitivityRow", "scaled_overrides", "run_sensitivity"]

PARAMETERS = ("shelf_height", "piece_distance", "pace", "transit_speed")


@dataclasses.dataclass(frozen=True)
class SensitivityRow:
    parameter: str
    factor: float
    table1_seeds: str
    """§7.1 seeds holding Table 1's shape, "k of n"."""
    robot_share: float
    share_by_action: dict[str, float]
    hrc_overruns: float
    robot_only_s: float
    rows_ok: int
    rows: int
    hrc_repetition_s: float = float("nan")
    """Mean HRC repetition [s] (the robot's rhythm, paper §7.2)."""


_ON_SURFACE_MARGIN = 0.05
"""How far inside its surface's edge a moved piece stays [m] (a piece is a few cm across)."""


def _moved_points(name: str, factor: float) -> dict[str, str]:
    """Every part's and place target's xy of the scenario's workcell moved ``factor`` times as far from the
    worker, kept on the surface it lies on (clamped :data:`_ON_SURFACE_MARGIN` inside its edges)."""
    sc = load_scenario(name)
    doc, spec = sc.cell_doc, parse_cell(sc.cell_doc, source=sc.cell_source)
    wx, wy = doc.get("worker", {}).get("xy", (0.0, 0.0))
    surfaces = list(spec.surfaces().values())
    out = {}
    for section in ("parts", "targets"):
        for key, entry in (doc.get(section) or {}).items():
            if not isinstance(entry, dict) or "xy" not in entry:
                continue
            x, y = entry["xy"]
            under = [u for u in surfaces if u.contains((x, y))]
            nx, ny = wx + (x - wx) * factor, wy + (y - wy) * factor
            if under:
                u = min(under, key=lambda u: -u.height)  # the top one
                nx, ny = u.clamp((nx, ny), _ON_SURFACE_MARGIN)
            out[f"scene.{section}.{key}.xy"] = f"{nx:.4f},{ny:.4f}"
    return out


def scaled_overrides(parameter: str, factor: float) -> dict[str, dict[str, str]]:
    """Overrides per scenario ("kwear-validation", "multi-subject") that move ``parameter`` by ``factor``."""
    if parameter not in PARAMETERS:
        raise ValueError(f"unknown parameter {parameter!r}; parameters: {', '.join(PARAMETERS)}")
    out: dict[str, dict[str, str]] = {"kwear-validation": {}, "multi-subject": {}}
    for name, over in out.items():
        scenario = load_scenario(name)
        cfg = scenario.protocol
        if parameter == "pace":
            over["pace"] = repr(cfg.population.pace * factor)
        elif parameter == "transit_speed":
            over["transit_speed"] = repr(cfg.robot.transit_speed * factor)
        elif parameter == "piece_distance":
            over.update(_moved_points(name, factor))
    if parameter == "shelf_height":
        shelf = load_scenario("kwear-validation").cell_doc["furniture"]["shelf"]
        out["kwear-validation"]["scene.furniture.shelf.height"] = repr(shelf["height"] * factor)
    return out


def run_sensitivity(plan: Plan, bounds: Bounds, out: Path, factors: tuple[float, ...] = (0.9, 1.1),
                    parameters: tuple[str, ...] = PARAMETERS, jobs: int | None = None,
                    log: Callable[[str], None] = lambda _msg: None) -> list[SensitivityRow]:
    rows = []
    for parameter in parameters:
        for factor in factors:
            over = scaled_overrides(parameter, factor)
            log(f"{parameter} x {factor:g}")
            runs = run_experiments(plan, Path(out) / f"{parameter}-{factor:g}", jobs=jobs, overrides=over)
            rows.append(_row(parameter, factor, runs, bounds))
    return rows


def _row(parameter: str, factor: float, runs: Runs, bounds: Bounds) -> SensitivityRow:
    checks = fidelity_rows(runs, bounds)
    shape = next(r for r in checks if r.figure.startswith("seeds holding"))
    ms = list(runs.multi_subject.values())
    actions = ("a1", "a2", "a3", "a4")
    by_action = {a: statistics.fmean(s["modes"]["hrc"]["robot_share_by_action"].get(a, 0.0) for s in ms)
                 for a in actions}
    reps = [r["duration_s"] for s in ms for r in s["modes"]["hrc"].get("repetitions", [])
            if r.get("duration_s") is not None]
    over = statistics.fmean(s["modes"]["hrc"]["takt_overruns"]
                            / max(1, s["modes"]["hrc"]["repetitions_completed"]) for s in ms)
    return SensitivityRow(parameter, factor, shape.twin,
                          statistics.fmean(s["modes"]["hrc"]["robot_share"] for s in ms), by_action, over,
                          robot_only_time(runs.robot_only), sum(r.ok for r in checks), len(checks),
                          statistics.fmean(reps) if reps else float("nan"))
