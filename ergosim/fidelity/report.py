"""The fidelity report: rows as a printed table with ✓/✗, ``fidelity.json`` and the side-by-side figure."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ergosim.atomic import write_json
from ergosim.fidelity.checks import Row, table1_of
from ergosim.fidelity.experiments import Plan, Runs
from ergosim.fidelity.figure import fidelity_figure

__all__ = ["report_text", "fidelity_document", "write_report"]


def report_text(rows: Sequence[Row], plan: Plan) -> str:
    """The twin-vs-paper table, one row a line, ✓ or ✗ first, then the count."""
    w_fig = max(len(r.figure) for r in rows)
    w_pap = max(len(r.paper) for r in rows)
    w_twin = max(len(r.twin) for r in rows)
    lines = [f"fidelity report ({plan.name} form): the twin against shared/paper.tex §7",
             f"  {'':4} {'figure':<{w_fig}}  {'paper':<{w_pap}}  {'twin':<{w_twin}}  bound"]
    section = None
    for r in rows:
        if r.section != section:
            section = r.section
            lines.append(section)
        mark = "✓" if r.ok else "✗"
        lines.append(f"  {mark:4} {r.figure:<{w_fig}}  {r.paper:<{w_pap}}  {r.twin:<{w_twin}}  {r.bound}"
                     + (f"  [{r.reading}]" if r.reading else ""))
    passed = sum(r.ok for r in rows)
    lines.append(f"{passed} of {len(rows)} rows within their bounds")
    return "\n".join(lines)


def fidelity_document(rows: Sequence[Row], runs: Runs, plan: Plan) -> dict:
    """``fidelity.json``: the rows, the figures behind them, and where each run's outputs are."""
    ms = runs.multi_subject
    return {
        "form": plan.name,
        "plan": {"kv_seeds": list(runs.kwear_validation), "ms_seeds": list(ms),
                 "ms_subjects": plan.ms_subjects, "ms_reps": plan.ms_reps,
                 "robot_only_subjects": plan.robot_only_subjects},
        "rows": [r.to_dict() for r in rows],
        "passed": sum(r.ok for r in rows),
        "total": len(rows),
        "kwear_validation": {str(seed): {"hrc": table1_of(s, "hrc"), "rula": table1_of(s, "rula"),
                                         "rula_g_by_action": s["rula_g_by_action"],
                                         "most_loaded_joint_by_action":
                                             s["calibration"]["most_loaded_joint_by_action"]}
                             for seed, s in runs.kwear_validation.items()},
        "multi_subject": {
            "robot_share": {str(seed): s["modes"]["hrc"]["robot_share"] for seed, s in ms.items()},
            "robot_share_by_action": {str(seed): s["modes"]["hrc"]["robot_share_by_action"]
                                      for seed, s in ms.items()},
            "rula_g_by_action": {str(seed): s["rula_g_by_action"] for seed, s in ms.items()},
            "wilcoxon": {str(seed): s.get("wilcoxon") for seed, s in ms.items()},
        },
        "runs": runs.folders,
    }


def write_report(out: Path, rows: Sequence[Row], runs: Runs, plan: Plan) -> dict:
    """Write ``out/fidelity.json`` and ``out/fidelity.png``; return the document."""
    doc = fidelity_document(rows, runs, plan)
    write_json(Path(out) / "fidelity.json", doc)
    fidelity_figure(doc, Path(out) / "fidelity.png")
    return doc
