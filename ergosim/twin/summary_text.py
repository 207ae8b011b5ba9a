"""The readable end-of-run summary printed by ``ergosim run``."""

from __future__ import annotations

__all__ = ["summary_text"]


def summary_text(summary: dict, cfg) -> str:
    lines = [f"scenario {summary.get('scenario')} (seed {summary.get('seed')})"
             + ("" if summary.get("complete", True) else "  [INCOMPLETE: interrupted]")]
    modes = summary.get("modes", {})
    lines.append(f"{'mode':<8} {'reps':>5} {'overruns':>9} {'robot share':>12}  by action")
    for mode, m in modes.items():
        by = "  ".join(f"{a} {100 * s:3.0f}%" for a, s in sorted(m["robot_share_by_action"].items()))
        share = "-"
        if m["actions"]:
            share = f"{100 * m['robot_share']:5.1f}% ({m['robot_actions']}/{m['actions']})"
        lines.append(f"{mode:<8} {m['repetitions_completed']:>5} {m['takt_overruns']:>9} {share:>12}  {by}")
    for key, label in (("kwear_integral_by_subject", "KWear integral ∫ΣV dt over repetitions × takt [s]"),
                       ("kwear_integral_run_by_subject", "KWear integral over the whole run [s]"),
                       ("duration_by_subject", "run duration [s]")):
        loads = {mode: m.get(key, []) for mode, m in modes.items()}
        if any(loads.values()):
            lines.append(f"{label}: " + "; ".join(
                f"{mode} mean {sum(v) / len(v):.1f}" for mode, v in loads.items() if v))
    tests = summary.get("wilcoxon_by_metric") or {"kwear_integral": summary.get("wilcoxon") or {}}
    for w in tests.values():
        if w.get("p") is not None:
            lines.append(f"Wilcoxon signed-rank ({w['metric']}, hrc vs h-only, n={w['n']}): "
                         f"W = {w['statistic']:g}, p = {w['p']:.3g}")
    table = summary.get("allocation_table")
    if table:
        for key, rows in table.items():
            lines.append(f"allocation table ({key}):")
            lines.extend(f"  rp{i + 1}: " + " ".join(r) for i, r in enumerate(rows))
    cal = summary.get("calibration", {})
    etas = cal.get("eta_by_subject", [])
    if etas:
        flat = [e for d in etas for e in d.values()]
        lines.append(f"calibration η: min {min(flat)}, max {max(flat)} (η0 = {cfg.eta0}, "
                     f"η_max = {cfg.eta_max}, Ṽ_des = {cfg.v_des:g})")
    return "\n".join(lines)
