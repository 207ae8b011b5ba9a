"""What report.html says, section by section, read from the run folder's own files (never the run's memory),
so ``ergosim report DIR`` writes the same page the run wrote.

Read: ``run.json`` (the protocol), ``summary.json`` (shares, overruns, durations, G(a_k), the tests),
``allocations.csv`` (refusals), ``decisions.csv`` (each decision's reason), ``failures.csv``,
``kwear_actions.csv`` (each action once from zero wear), and the PNGs beside them (``cell.png``, the
figures).
"""

from __future__ import annotations

import csv
import json
import os
from collections import defaultdict
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.experiment.report.page import data_uri, details, esc, image, para, section, table
from ergosim.experiment.summary_text import SHARE_WORDS, overrun_words, wilcoxon_lines
from ergosim.posture import KWEAR_JOINTS

__all__ = ["RunFiles", "read_run", "sections"]

VIDEO_INLINE_BYTES = 4_000_000
"""A video up to this size is embedded in the page (a data URI), a larger one is linked (assumed: a page
of a few MB still opens at once in a browser)."""


class RunFiles:
    """The run folder ``out`` read for the page: ``manifest`` (run.json), ``summary`` (summary.json) and the
    CSV files as lists of dict rows (empty when a file is missing)."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.manifest = _json(out, "run.json")
        self.summary = _json(out, "summary.json")
        self.config = self.summary.get("config") or self.manifest.get("config", {})
        self.allocations = _rows(out / "allocations.csv")
        self.decisions = _rows(out / "decisions.csv")
        self.failures = _rows(out / "failures.csv")
        self.traces = _rows(out / "kwear_actions.csv")

    def modes(self) -> list[tuple[str, dict]]:
        """(mode, its summary) in the order the run ran them."""
        got = self.summary.get("modes", {})
        return [(m, got[m]) for m in self.config.get("modes", got) if m in got]


def _json(out: Path, name: str) -> dict:
    try:
        return json.loads((out / name).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"no {name} in {out}: not the folder of a finished `ergosim run`",
                          where=str(out)) from None
    except (OSError, ValueError) as err:
        raise ConfigError(f"cannot read {name}: {err}", where=str(out)) from None


def _rows(path: Path) -> list[dict]:
    if not path.is_file():
        return []
    with path.open(encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def read_run(out: str | os.PathLike[str]) -> RunFiles:
    out = Path(out)
    if not out.is_dir():
        raise ConfigError(f"{out} is not a directory", where="ergosim report")
    return RunFiles(out)


def _header(r: RunFiles) -> str:
    s, cfg = r.summary, r.config
    status = s.get("status", r.manifest.get("status", "?"))
    subjects = s.get("subjects_finished", len(s.get("subjects", [])))
    facts = [f"seed {s.get('seed')}", f"task {cfg.get('task')}", f"{subjects} subject(s)",
             f"{cfg.get('repetitions')} repetition(s) per subject and mode", f"takt {cfg.get('takt'):g} s",
             f"modes {', '.join(cfg.get('modes', []))}", f"status {status}",
             f"ergosim {r.manifest.get('ergosim', '?')}"]
    warn = "" if status == "complete" else para(
        f"This run is {status}: the page shows what its files hold, not the whole experiment.", "note")
    return (f"<h1>ergosim run: {esc(s.get('scenario'))}</h1>\n<p class=\"meta\">{esc(' · '.join(facts))}</p>"
            + warn)


def _still(r: RunFiles) -> str:
    png = r.out / "cell.png"
    if png.is_file():
        body = image(png, "The workcell as the run built it, before the first tick: the worker at rest, the "
                          "parts where they are laid out.", "the workcell")
    else:
        body = para("No still of the workcell in this folder (the run drew no figures, or this machine "
                    "could not open an OpenGL context); `ergosim render SCENARIO --out cell.png` makes one.",
                    "note")
    return section("The workcell", [body], "cell")


def _results(r: RunFiles) -> str:
    rows = []
    for mode, m in r.modes():
        reps = f"{m.get('repetitions_completed', 0)}/{len(m.get('repetitions', []))}"
        integral = m.get("kwear_integral_by_subject") or []
        above = m.get("time_above_vth_by_subject") or []
        rows.append([mode, reps, m.get("repetitions_abandoned", 0), m.get("takt_overruns", 0),
                     _pct(m, "robot_share", "robot_actions", "actions"),
                     _pct(m, "robot_share_chosen", "robot_choices", "choices"),
                     f"{sum(integral) / len(integral):.1f}" if integral else "-",
                     f"{sum(above) / len(above):.1f}" if above else "-"])
    head = ["mode", "repetitions done", "abandoned", "takt overruns", "robot share", "of choices",
            "KWear integral, mean [s]", "time above V_th, mean [s]"]
    parts = [table(head, rows, classes=["", "n", "n", "n", "n", "n", "n", "n"]),
             *(para(w) for w in SHARE_WORDS),
             para(f"KWear integral: ∫ Σ V dt over the production schedule (repetitions × takt), the physical "
                  f"load of the worker's five joints; time above V_th: how long any joint's KWear was at or "
                  f"above its threshold V_th = {r.config.get('v_th', float('nan')):g}.")]
    parts += [para(line) for line in wilcoxon_lines(r.summary)]
    return section("What the run says", parts, "results")


def _pct(m: dict, share: str, robot: str, total: str) -> str:
    return f"{100 * m[share]:.1f} % ({m[robot]}/{m[total]})" if m.get(total) else "-"


def _takt(r: RunFiles) -> str:
    parts = [para(line) for line in overrun_words(r.summary, r.config)]
    return section("Takt and overruns", parts, "takt")


def _mark_class(text: str) -> str:
    return {"H": "H", "R": "R", "x": "x", "-": "d"}.get(text[:1], "")


def _allocations(r: RunFiles) -> str:
    actions = r.summary.get("action_labels", [])
    parts = [para("Who completed each action in each repetition (the twin's Table 1): H the worker, R a "
                  "robot, * forced (failures earlier in the repetition left only this agent), ! after a "
                  "failed attempt, - not done, x no agent left.")]
    for mode, m in r.modes():
        rows = [[f"subject {x['subject']} rep {x['repetition']}",
                 *(x["cells"].get(a, "-") for a in actions), x.get("outcome") or ""]
                for x in m.get("allocation_rows", [])]
        parts.append(f"<h3>{esc(mode)}</h3>")
        parts.append(table(["", *actions, "outcome"], rows,
                           cell_class=lambda t: "" if t.startswith("subject") or t.isalpha() and len(t) > 1
                           else _mark_class(t)))
    return section("Allocation per mode", parts, "allocations")


def _per_action(r: RunFiles) -> str:
    s = r.summary
    rula, reba = s.get("rula_g_by_action", {}), s.get("reba_g_by_action", {})
    loaded = s.get("calibration", {}).get("most_loaded_joint_by_action", {})
    ends: dict[str, list[list[float]]] = defaultdict(list)
    last: dict[tuple[str, str], list[float]] = {}
    for row in r.traces:  # each execution's last row: the KWear it leaves behind from zero wear
        last[(row["subject"], row["action"])] = [float(row[f"kwear_{j}"]) for j in KWEAR_JOINTS]
    for (_, action), v in last.items():
        ends[action].append(v)
    head = ["action", "RULA G(a_k)", *(["REBA G(a_k)"] if reba else []), "most loaded joint",
            *(f"KWear {j}" for j in KWEAR_JOINTS)]
    rows = []
    for a in s.get("action_labels", []):
        got = ends[a]
        mean = [sum(v[k] for v in got) / len(got) for k in range(len(KWEAR_JOINTS))] if got else []
        rows.append([a, f"{rula[a]:g}" if a in rula else "-", *([f"{reba.get(a, float('nan')):g}"] if reba
                                                                 else []),
                     loaded.get(a, "-"), *(f"{x:.3f}" for x in mean or ["-"] * len(KWEAR_JOINTS))])
    n = len({subject for subject, _ in last})
    text = (f"G(a_k): the action's RULA grand score (1-7; median over the subjects' calibration executions), "
            f"the static baseline's measure. KWear per execution: each joint's KWear V after the worker does "
            f"the action once from zero wear (mean over {n} subject(s), their first calibration execution); "
            f"V_th = {r.config.get('v_th', float('nan')):g}. The most loaded joint wears the most per "
            f"execution (largest 1 - α) for most subjects.")
    return section("Per action: RULA score and KWear per execution",
                   [table(head, rows, classes=["", "n", *(["n"] if reba else []), "",
                                               *["n"] * len(KWEAR_JOINTS)]), para(text)],
                   "actions")


_FIGURES = (
    ("kwear_timeline_{mode}.png", "KWear per joint over the run in mode {mode}, a panel per subject: V_th, "
                                  "dotted lines where repetitions start, grey where a robot acts, a strip of "
                                  "every attempt (blue the worker, red a robot, hatched a failed one)."),
    ("kwear_modes.png", "Per subject, mode against mode: the KWear integral, the highest V reached "
                        "against V_th and the time above V_th (a line joins a subject's values; bars are the "
                        "means)."),
    ("allocation_histogram.png", "The robot's share of each action per mode, each bar labelled robot / "
                                 "completed."),
    ("kwear_actions.png", "The paper's KWear figure: each action once from zero wear, the five joints' V."),
)


def _figures(r: RunFiles) -> str:
    parts = []
    for name, caption in _FIGURES:
        for mode in r.config.get("modes", []) if "{mode}" in name else [""]:
            path = r.out / name.format(mode=mode)
            if path.is_file():
                parts.append(image(path, caption.format(mode=mode), path.stem))
    if not parts:
        parts.append(para("No figures in this folder (`ergosim run --no-plots`); `ergosim plot DIR` draws "
                          "them, then `ergosim report DIR` puts them here.", "note"))
    return section("Wear over the run", parts, "figures")


def _failures(r: RunFiles) -> str:
    refused = [a for a in r.allocations if a.get("status") == "refused"]
    parts = []
    if r.failures:
        parts.append(table(["time [s]", "subject", "mode", "rep", "action", "agent", "status", "message"],
                           [[x["time"], x["subject"], x["mode"], x["repetition"], x["action"], x["agent"],
                             x["status"], x["message"]] for x in r.failures], classes=["n", "n", "", "n"]))
    else:
        parts.append(para("No failed attempt and no abandoned repetition.", "ok"))
    if refused:
        parts.append(para(f"The worker refused {len(refused)} assignment(s) (negotiation); each refusal took "
                          "that (action, agent) out of the decision and the allocator planned again:"))
        parts.append(table(["time [s]", "subject", "mode", "rep", "action", "refused by"],
                           [[a["t_start"], a["subject"], a["mode"], a["repetition"], a["action"], a["agent"]]
                            for a in refused], classes=["n", "n", "", "n"]))
    return section("Failures and refusals", parts, "failures")


def _decisions(r: RunFiles) -> str:
    if not r.decisions:
        none = para("No decisions recorded in this folder.", "note")
        return section("Each decision and its reason", [none], "decisions")
    groups: dict[tuple[str, str], list[dict]] = defaultdict(list)
    for d in r.decisions:
        groups[(d["mode"], d["subject"])].append(d)
    parts = [para("Every allocation decision, with the reason the allocator kept as data, in words: the "
                  "predicted KWear against V_th and the costs the planner compared.")]
    for k, ((mode, subject), rows) in enumerate(groups.items()):
        inner = table(["time [s]", "rep", "action", "agent", "reason"],
                      [[d["time"], d["repetition"], d["action"], d["agent"], d["reason"]] for d in rows],
                      classes=["n", "n"])
        parts.append(details(f"{mode}, subject {subject}: {len(rows)} decision(s)", inner, open_=k == 0))
    return section("Each decision and its reason", parts, "decisions")


def _video(r: RunFiles, video: Path | None) -> str:
    if video is None or not video.is_file():
        return ""
    if video.stat().st_size <= VIDEO_INLINE_BYTES:
        body = (f"<video controls width=\"960\" src=\"{data_uri(video, 'video/mp4')}\"></video>"
                f"<p class=\"meta\">{esc(video.name)}, embedded in this page.</p>")
    else:
        rel = os.path.relpath(video.resolve(), r.out.resolve())
        body = (f"<p><a href=\"{esc(Path(rel).as_posix())}\">{esc(video.name)}</a> (too large to embed: "
                f"{video.stat().st_size / 1e6:.0f} MB; hand it on beside this page).</p>")
    return section("Video", [body], "video")


def sections(r: RunFiles, video: Path | None = None) -> list[str]:
    """The page's parts in order."""
    return [_header(r), _still(r), _results(r), _takt(r), _allocations(r), _per_action(r), _figures(r),
            _failures(r), _decisions(r), _video(r, video)]
