"""The twin-vs-paper rows of the fidelity report, each with its acceptance bound (issues 13 and 23).

A :class:`Row` holds the paper's figure, the twin's, whether the twin is within the bound, and the reading of
the protocol the figure was measured under (how the repetitions were paced). The full bounds are issue 23's
acceptance criteria; the ``quick`` bounds are looser, for the reduced runs CI makes (fewer subjects and
seeds give noisier shares and weaker statistics, so the quick form checks the shape: the ordering of the
actions, no H-only overrun, a clear HRC benefit).
"""

from __future__ import annotations

import dataclasses
import statistics
from collections.abc import Mapping, Sequence

from ergosim.fidelity import paper
from ergosim.fidelity.experiments import Runs

__all__ = ["Row", "Bounds", "FULL_BOUNDS", "QUICK_BOUNDS", "fidelity_rows", "table1_of", "robot_only_time",
           "pacing_of"]


@dataclasses.dataclass(frozen=True)
class Row:
    """One line of the report: ``paper`` and ``twin`` as printed, ``ok`` against ``bound`` (in words)."""

    section: str
    figure: str
    paper: str
    twin: str
    ok: bool
    bound: str
    reading: str = ""
    """How the repetitions behind the figure were paced (§7.2 rows): "HRC: robot's rhythm, H only: ..."."""

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class Bounds:
    """Acceptance bounds. Shares are fractions; times in seconds."""

    table1_seeds_needed: int
    share_range: tuple[float, float]
    a2_min: float
    a34_max: float
    hrc_repetition_tolerance: float
    """Mean HRC repetition within this fraction of T_takt = 38 s (the robot set the rhythm)."""
    robot_only_tolerance: float
    """The r-only repetition, hand-overs included, within this fraction of 38 s."""
    delivery_tolerance: float
    """The robot's own delivery of a1-a4's parts within this fraction of 38 s."""
    p_max: float
    g_tolerance: int = 1


FULL_BOUNDS = Bounds(table1_seeds_needed=4, share_range=(0.30, 0.46), a2_min=0.60, a34_max=0.25,
                     hrc_repetition_tolerance=0.20, robot_only_tolerance=0.30, delivery_tolerance=0.20,
                     p_max=0.01)
QUICK_BOUNDS = Bounds(table1_seeds_needed=1, share_range=(0.15, 0.60), a2_min=0.35, a34_max=0.40,
                      hrc_repetition_tolerance=0.35, robot_only_tolerance=0.45, delivery_tolerance=0.35,
                      p_max=0.05)


def table1_of(summary: Mapping, mode: str) -> list[str]:
    """Per repetition of subject 0, the allocation of the summary's actions as a string such as "HRHHH"
    (H worker, R robot; "-" for an action not done)."""
    rows = [r for r in summary["modes"][mode]["allocation_rows"] if r["subject"] == 0]
    actions = summary["action_labels"]
    return ["".join(r["cells"][a][:1] if r["cells"][a][:1] in "HR" else "-" for a in actions) for r in rows]


def _table1_holds(kwear: Sequence[str], rula: Sequence[str]) -> bool:
    """§7.1's shape: rp1 all H; 1 or 2 robot actions in each of rp2..rp4; the RULA baseline all H."""
    if len(kwear) < 4 or any("-" in rep for rep in kwear):
        return False
    return (kwear[0] == "HHHHH" and all(1 <= rep.count("R") <= 2 for rep in kwear[1:4])
            and all(rep == paper.TABLE1_RULA for rep in rula))


def pacing_of(summary: Mapping) -> str:
    """How a run's repetitions were paced, in words: every mode at its takt slot (``takt_paced``), or the
    collaborative modes back to back (the robot's rhythm) and H only by the chronometer (paper §7.2)."""
    paced = bool(summary.get("config", {}).get("takt_paced", False))
    return "every mode at its takt slot" if paced else "HRC: robot's rhythm, H only: chronometer"


def _mean_hrc_repetition(summary: Mapping) -> float:
    reps = [r["duration_s"] for r in summary["modes"]["hrc"].get("repetitions", [])
            if r.get("outcome") == "completed" and r.get("duration_s") is not None]
    return statistics.fmean(reps) if reps else float("nan")


def robot_only_time(timing: Mapping) -> float:
    """Mean duration [s] of the r-only repetitions: the robot's whole assembly, parts taken by the worker."""
    return float(timing["repetition_mean_s"]) if timing.get("completed") else float("nan")


def _g_rows(section: str, summaries: Sequence[Mapping], target: Mapping[str, int], bounds: Bounds,
            riskiest: str | None) -> list[Row]:
    actions = list(target)
    g = {a: statistics.median(s["rula_g_by_action"][a] for s in summaries) for a in actions}
    within = all(abs(g[a] - target[a]) <= bounds.g_tolerance for a in actions)
    twin = " ".join(f"{g[a]:g}" for a in actions)
    published = " ".join(str(target[a]) for a in actions)
    rows = [Row(section, "G(a1..a5), RULA (the worst posture held 1 s)", published, twin, within,
                f"each within ±{bounds.g_tolerance}")]
    if riskiest is not None:
        top = max(g.values())
        rows.append(Row(section, "riskiest action (highest G)", riskiest,
                        ",".join(a for a in actions if g[a] == top), g[riskiest] == top and
                        sum(v == top for v in g.values()) == 1, f"{riskiest} alone"))
    return rows


def _loaded_rows(summaries: Sequence[Mapping]) -> list[Row]:
    want = paper.LOADED_JOINT_KWEAR_VALIDATION
    got = {a: [s["calibration"]["most_loaded_joint_by_action"][a] for s in summaries] for a in want}
    # a tie goes to the joint the seeds named first, so the row does not depend on string hashing
    majority = {a: max(dict.fromkeys(v), key=v.count) for a, v in got.items()}
    return [Row("§7.1", "most-loaded joint of a1 / a2 / a5 (largest 1 - α)", " / ".join(want.values()),
                " / ".join(majority.values()), all(majority[a] == want[a] for a in want),
                "the same joint in most seeds")]


def fidelity_rows(runs: Runs, bounds: Bounds) -> list[Row]:
    """Every row of the report from the experiments' summaries."""
    rows: list[Row] = []
    # -- §7.1 ------------------------------------------------------------------------------------------
    kv = runs.kwear_validation
    holds = {}
    for seed, s in kv.items():
        holds[seed] = _table1_holds(table1_of(s, "hrc"), table1_of(s, "rula"))
    first = kv[min(kv)]
    rows.append(Row("§7.1", "Table 1, KWear allocation rp1..rp4 (seed 0)", " ".join(paper.TABLE1_KWEAR),
                    " ".join(table1_of(first, "hrc")), holds[min(kv)],
                    "rp1 all H, 1-2 R in each of rp2-rp4, RULA all H"))
    needed = min(bounds.table1_seeds_needed, len(kv))
    rows.append(Row("§7.1", f"seeds holding that shape ({len(kv)} seeds)", "-",
                    f"{sum(holds.values())} of {len(kv)}", sum(holds.values()) >= needed, f">= {needed}"))
    rula = [rep for s in kv.values() for rep in table1_of(s, "rula")]
    rows.append(Row("§7.1", "RULA-baseline allocation", paper.TABLE1_RULA + " every rp",
                    "all H" if all(r == paper.TABLE1_RULA for r in rula) else "robot used",
                    all(r == paper.TABLE1_RULA for r in rula), "all H"))
    rows += _g_rows("§7.1", list(kv.values()), paper.G_KWEAR_VALIDATION, bounds, None)
    rows += _loaded_rows(list(kv.values()))
    # -- §7.2 ------------------------------------------------------------------------------------------
    ms = runs.multi_subject
    shares = {seed: s["modes"]["hrc"]["robot_share"] for seed, s in ms.items()}
    by_action = {seed: s["modes"]["hrc"]["robot_share_by_action"] for seed, s in ms.items()}
    lo, hi = bounds.share_range
    rows.append(Row("§7.2", "robot share of a1-a4 (HRC)", f"{paper.ROBOT_SHARE:.0%}",
                    " / ".join(f"{v:.1%}" for v in shares.values()),
                    all(lo <= v <= hi for v in shares.values()), f"{lo:.0%}-{hi:.0%} in every seed"))
    a = ("a1", "a2", "a3", "a4")
    mean_by = {x: statistics.fmean(b.get(x, 0.0) for b in by_action.values()) for x in a}
    rows.append(Row("§7.2", "robot share a1 / a2 / a3 / a4",
                    " / ".join(f"{paper.ROBOT_SHARE_BY_ACTION[x]:.0%}" for x in a),
                    " / ".join(f"{mean_by[x]:.0%}" for x in a),
                    all(b.get("a2", 0) >= bounds.a2_min and b.get("a2", 0) == max(b.get(x, 0) for x in a)
                        for b in by_action.values()), f"a2 >= {bounds.a2_min:.0%} and the highest"))
    rows.append(Row("§7.2", "a3 and a4 to the robot", "10 % each",
                    " / ".join(f"{b.get('a3', 0):.0%}, {b.get('a4', 0):.0%}" for b in by_action.values()),
                    all(max(b.get("a3", 0), b.get("a4", 0)) <= bounds.a34_max for b in by_action.values()),
                    f"<= {bounds.a34_max:.0%}"))
    between = all(max(b.get("a3", 0), b.get("a4", 0)) <= b.get("a1", 0) <= b.get("a2", 0)
                  for b in by_action.values())
    rows.append(Row("§7.2", "a1 between a3/a4 and a2", "10 % <= 51 % <= 78 %",
                    " / ".join(f"{b.get('a1', 0):.0%}" for b in by_action.values()), between,
                    "in every seed"))
    takt = paper.TAKT_S
    rep = {seed: _mean_hrc_repetition(s) for seed, s in ms.items()}
    tol_rep = bounds.hrc_repetition_tolerance
    rows.append(Row("§7.2", "mean HRC repetition [s]", f"{takt:g} (the robot set the rhythm)",
                    " / ".join(f"{v:.1f}" for v in rep.values()),
                    all(abs(v - takt) <= tol_rep * takt for v in rep.values()),
                    f"{takt:g} s ± {tol_rep:.0%}"))
    h_over = {seed: s["modes"]["h-only"]["takt_overruns"] for seed, s in ms.items()}
    rows.append(Row("§7.2", "H-only repetitions over the takt", "none (workers waited for the chronometer)",
                    " / ".join(str(v) for v in h_over.values()), all(v == 0 for v in h_over.values()), "0"))
    t_robot = robot_only_time(runs.robot_only)
    tol = bounds.robot_only_tolerance
    rows.append(Row("§7.2", "robot-only assembly, r-only repetition, hand-overs included [s]",
                    f"{paper.ROBOT_ONLY_S:g}", f"{t_robot:.1f}",
                    abs(t_robot - paper.ROBOT_ONLY_S) <= tol * paper.ROBOT_ONLY_S,
                    f"{paper.ROBOT_ONLY_S:g} s ± {tol:.0%}"))
    delivery = float(runs.robot_only.get("delivery_mean_s", float("nan")))
    tol_d = bounds.delivery_tolerance
    rows.append(Row("§7.2", "robot bringing a1-a4's parts, its own motion [s]", f"{paper.ROBOT_ONLY_S:g}",
                    f"{delivery:.1f}", abs(delivery - paper.ROBOT_ONLY_S) <= tol_d * paper.ROBOT_ONLY_S,
                    f"{paper.ROBOT_ONLY_S:g} s ± {tol_d:.0%}"))
    ps = {seed: (s.get("wilcoxon") or {}).get("p", float("nan")) for seed, s in ms.items()}
    lower = {seed: statistics.fmean(s["modes"]["hrc"]["kwear_integral_by_subject"])
             < statistics.fmean(s["modes"]["h-only"]["kwear_integral_by_subject"]) for seed, s in ms.items()}
    rows.append(Row("§7.2", "Wilcoxon HRC vs H only, KWear integral", "p < 0.01 (physical demand), HRC lower",
                    " / ".join(f"p = {v:.2g}{'' if lower[k] else ' (HRC higher)'}" for k, v in ps.items()),
                    all(v < bounds.p_max and lower[k] for k, v in ps.items()),
                    f"p < {bounds.p_max:g}, HRC lower"))
    rows += _g_rows("§7.2", list(ms.values()), paper.G_MULTI_SUBJECT, bounds, "a2")
    readings = sorted({pacing_of(s) for s in ms.values()})
    paced = ("robot share", "a3 and a4", "a1 between", "mean HRC", "H-only", "Wilcoxon")
    return [dataclasses.replace(r, reading=" | ".join(readings))
            if r.section == "§7.2" and r.figure.startswith(paced) else r for r in rows]
