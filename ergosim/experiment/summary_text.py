"""The readable end-of-run summary printed by ``ergosim run``.

It says what happened, not only what was planned: the robot share counts completed actions (forced ones
too, failed attempts never), a warning line names every forced decision, failure and abandoned
repetition, and each mode's allocation table has a labelled row per subject and repetition.
"""

from __future__ import annotations

import textwrap

from ergosim.experiment.summary import too_few_pairs
from ergosim.twin.modes import mode_or_default

__all__ = ["summary_text", "warning_lines", "overrun_words", "wilcoxon_lines", "too_few_words", "SHARE_WORDS"]

_LEGEND = "H worker, R robot, * forced, ! after a failed attempt, - not done, x no agent left"

SHARE_WORDS = (
    "robot share: of the completed actions that the task lets either agent do, the fraction a robot "
    "completed (a forced robot action counts, a failed attempt does not).",
    "of choices: of the decisions at which the allocator could give the action to either agent, the fraction "
    "it gave a robot (failed and refused attempts count). An action the robot cannot do in this cell (its "
    "reach, gripper or payload), or one that earlier failures left to one agent, is no choice: it counts in "
    "robot share but not here, so the two differ most where the robot is refused much of the task.",
)
"""What the two robot shares of the summary mean (printed under the table, and in report.html)."""


def overrun_words(summary: dict, config: dict) -> list[str]:
    """The takt and each mode's overruns in words: what the takt is, the schedule it sets, and how long the
    repetitions took against it."""
    takt, reps = config.get("takt"), config.get("repetitions")
    if not takt:
        return []
    lines = [f"takt {takt:g} s: the time the line gives one repetition; the schedule is {reps} × {takt:g} s "
             f"= {reps * takt:g} s per subject and mode (the window of the KWear integral), and a repetition "
             "that takes longer than the takt is an overrun."]
    modes = summary.get("modes", {})
    for mode in [m for m in config.get("modes", modes) if m in modes]:
        m = modes[mode]
        took = [r["duration_s"] for r in m.get("repetitions", []) if r.get("duration_s") is not None]
        over = m.get("takt_overruns", 0)
        if not took:
            lines.append(f"{mode}: {over} overrun(s)")
            continue
        span = (f"{min(took):.1f} s" if len(took) == 1 else
                f"{min(took):.1f}-{max(took):.1f} s (mean {sum(took) / len(took):.1f} s)")
        verdict = ("so this mode does not hold the takt in this cell" if over == len(took)
                   else "" if over else "every one within it")
        lines.append(f"{mode}: {over} of {len(took)} repetition(s) over the {takt:g} s takt (repetitions "
                     f"took {span})" + (f", {verdict}" if verdict else ""))
    return lines


def too_few_words(n: int) -> str:
    """Why no test is printed for ``n`` pairs."""
    return (f"n = {n} pair{'s' if n != 1 else ''}, too few for a Wilcoxon signed-rank test (below 6 pairs "
            "its two-sided p cannot fall below 0.05 whatever the data)")


def wilcoxon_lines(summary: dict) -> list[str]:
    """The paired tests of summary.json, a line each, naming the modes compared; one line saying so instead
    when there are too few pairs (:func:`~ergosim.experiment.summary.too_few_pairs`)."""
    tests = summary.get("wilcoxon_by_metric") or {"kwear_integral": summary.get("wilcoxon") or {}}
    tests = [w for w in tests.values() if w.get("n")]
    if not tests:
        return []
    pair = " vs ".join(tests[0].get("modes") or ["the paired modes"])
    if too_few_pairs(tests[0]["n"]):
        return [f"Wilcoxon signed-rank, {pair}, subject by subject: not computed: "
                f"{too_few_words(tests[0]['n'])}"]
    return [f"Wilcoxon signed-rank ({w['metric']}, {pair}, n={w['n']}): W = {w['statistic']:g}, "
            f"p = {w['p']:.3g}" for w in tests if w.get("p") is not None]


def _share(m: dict, share: str, robot: str, total: str) -> str:
    if not m.get(total):
        return "-"
    return f"{100 * m[share]:5.1f}% ({m[robot]}/{m[total]})"


def warning_lines(summary: dict) -> list[str]:
    """One ``WARNING`` line per mode with forced decisions, failed attempts or abandoned repetitions."""
    lines = []
    if not summary.get("complete", True) and summary.get("status") in ("interrupted", "failed", "running"):
        done, planned = summary.get("subjects_finished"), summary.get("subjects_planned")
        lines.append(f"WARNING: run {summary.get('status')}: {done} of {planned} subjects finished; "
                     "the files hold only those")
    for mode, m in summary.get("modes", {}).items():
        parts = []
        for key, what in (("forced_robot_actions", "forced robot action(s)"),
                          ("forced_human_actions", "forced worker action(s)"),
                          ("robot_failures", "robot failure(s)"),
                          ("worker_failures", "worker failure(s)"),
                          ("repetitions_abandoned", "repetition(s) abandoned"),
                          ("repetitions_not_run", "repetition(s) not run")):
            if m.get(key):
                parts.append(f"{m[key]} {what}")
        if parts:
            reps = m.get("repetitions", [])
            reasons = sorted({r["reason"] for r in reps if r.get("outcome") == "abandoned"})
            why = f" (abandoned: {'; '.join(reasons)})" if reasons else ""
            lines.append(f"WARNING: {mode}: " + ", ".join(parts) + why + "; see failures.csv")
    return lines


def _wrapped(paragraphs) -> list[str]:
    """Each paragraph wrapped at 110 columns, its follow-on lines indented."""
    return [line for text in paragraphs for line in textwrap.wrap(text, 110, subsequent_indent="    ")]


def _table(mode: str, rows: list[dict], actions: list[str]) -> list[str]:
    if not rows:
        return []
    label = [f"subject {r['subject']} rep {r['repetition']}" for r in rows]
    width = max(len(s) for s in label)
    cell = max([3, *(len(a) for a in actions), *(len(c) for r in rows for c in r["cells"].values())])
    lines = [f"allocations, {mode} ({_LEGEND}):",
             ("  " + " " * width + "  " + " ".join(a.ljust(cell) for a in actions)).rstrip()]
    for name, r in zip(label, rows, strict=True):
        tail = "" if r.get("outcome") in ("completed", "") else f"  {r['outcome']}"
        lines.append(("  " + name.ljust(width) + "  "
                      + " ".join(r["cells"].get(a, "-").ljust(cell) for a in actions)).rstrip() + tail)
    return lines


def summary_text(summary: dict, cfg) -> str:
    status = summary.get("status", "complete" if summary.get("complete", True) else "interrupted")
    flag = {"complete": "", "abandoned": "  [INCOMPLETE: repetitions abandoned]",
            "interrupted": "  [INCOMPLETE: interrupted]", "failed": "  [INCOMPLETE: failed]"}.get(status, "")
    lines = [f"scenario {summary.get('scenario')} (seed {summary.get('seed')})" + flag]
    modes = summary.get("modes", {})
    actions = summary.get("action_labels") or sorted({a for m in modes.values()
                                                      for a in m.get("robot_share_by_action", {})})
    lines.append(f"actions: {' '.join(actions) if actions else '-'}")
    w = max([8, *(len(m) for m in modes)])
    lines.append(f"{'mode':<{w}} {'reps done':>9} {'abandoned':>9} {'overruns':>8} {'robot share':>15} "
                 f"{'of choices':>15}  robot share by action")
    for mode, m in modes.items():
        by = "  ".join(f"{a} {100 * s:3.0f}%" for a, s in sorted(m["robot_share_by_action"].items()))
        planned = len(m.get("repetitions", [])) or m["repetitions_completed"]
        reps = f"{m['repetitions_completed']}/{planned}"
        lines.append(f"{mode:<{w}} {reps:>9} {m.get('repetitions_abandoned', 0):>9} {m['takt_overruns']:>8} "
                     f"{_share(m, 'robot_share', 'robot_actions', 'actions'):>15} "
                     f"{_share(m, 'robot_share_chosen', 'robot_choices', 'choices'):>15}  {by}")
    lines.extend(_wrapped(SHARE_WORDS))
    lines.extend(_wrapped(overrun_words(summary, summary.get("config") or {})))
    for key, label in (("kwear_integral_by_subject", "KWear integral ∫ΣV dt over repetitions × takt [s]"),
                       ("kwear_integral_run_by_subject", "KWear integral over the whole run [s]"),
                       ("duration_by_subject", "run duration [s]")):
        loads = {mode: m.get(key, []) for mode, m in modes.items()}
        if any(loads.values()):
            lines.append(f"{label}: " + "; ".join(
                f"{mode} mean {sum(v) / len(v):.1f}" for mode, v in loads.items() if v))
    reba = summary.get("reba_g_by_action")
    if reba:  # a mode read REBA: its G(a_k) beside RULA's
        rula = summary.get("rula_g_by_action", {})
        lines.append("G(a_k), RULA grand / REBA score (median over subjects): " + "  ".join(
            f"{a} {rula.get(a, float('nan')):g}/{g:g}" for a, g in reba.items()))
    lines.extend(_wrapped(wilcoxon_lines(summary)))
    for mode, m in modes.items():
        if mode_or_default(mode).uses_robot or m.get("repetitions_abandoned") or m.get("worker_failures"):
            lines.extend(_table(mode, m.get("allocation_rows", []), actions))
    cal = summary.get("calibration", {})
    etas = cal.get("eta_by_subject", [])
    if etas:
        flat = [e for d in etas for e in d.values()]
        lines.append(f"calibration η: min {min(flat)}, max {max(flat)} (η0 = {cfg.calibration.eta0}, "
                     f"η_max = {cfg.calibration.eta_max}, Ṽ_des = {cfg.calibration.v_des:g})")
    lines.extend(warning_lines(summary))
    return "\n".join(lines)
