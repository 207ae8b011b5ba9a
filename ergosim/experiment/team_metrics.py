"""Team figures of a run, per mode: what a researcher comparing sequential and parallel execution reads.

Computed from the subject runs alone (the allocations, the tick log's ``acting`` column, the robots' skill
spans, the negotiation's offers and the safety monitor's record), the same way for both executions:

- ``makespan_s``: per subject, each completed repetition's time from its start to its last action's end;
- ``throughput_per_hour``: 3600 × completed repetitions / Σ makespan, the rate the team sustains when each
  assembly starts as soon as the last one ends; ``paced_throughput_per_hour``: completed repetitions per
  hour of the run from the first repetition's start to the last one's end (on a paced line, at most 3600 /
  takt);
- ``takt_overruns``: repetitions longer than the takt;
- ``idle_s``: per agent, Σ over completed repetitions of the makespan minus the agent's busy time in it
  (the worker acting, a robot's skill running, home again included); ``idle_fraction`` of Σ makespan;
- ``both_busy_s``: time the worker and a robot were busy at once; ``overlapping_repetitions``: repetitions
  in which two agents' completed actions overlapped in time;
- ``kwear_integral``, ``time_above_vth_s``: the subjects' means (as ``*_by_subject`` of the mode);
- ``refusals``, ``offers`` and the refusal rate by the offered action's V̂ (negotiation);
- ``safety``: the smallest human-robot separation [m] over the subjects, the time the robots were slowed or
  stopped [s], the time any robot capsule overlapped the worker's, and the smallest separation at the end.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ergosim.twin.records import SubjectRun

__all__ = ["REFUSAL_BINS", "team_mode_metrics", "team_document", "team_in_summary"]

REFUSAL_BINS = (0.0, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0)
"""Edges of the V̂ bins of the refusal rate."""


def _busy(intervals: list[tuple[float, float]], lo: float, hi: float) -> float:
    """Length of the union of ``intervals`` inside [lo, hi] [s]."""
    total, end = 0.0, lo
    for start, stop in sorted(intervals):
        a, b = max(start, end), min(stop, hi)
        if b > a:
            total += b - a
            end = b
    return total


def _acting(run: SubjectRun) -> list[tuple[float, float]]:
    """The worker's acting intervals from the tick log (each 20 Hz tick stands for the period before it)."""
    rows = run.ticks.rows
    if not len(rows):
        return []
    t, acting = run.ticks.column("t"), run.ticks.column("acting") > 0.5
    return [(float(x) - run.dt_tick, float(x)) for x in t[acting]]


def _overlap(a: list[tuple[float, float]], b: list[tuple[float, float]], lo: float, hi: float) -> float:
    both = [(max(x0, y0), min(x1, y1)) for x0, x1 in a for y0, y1 in b if min(x1, y1) > max(x0, y0)]
    return _busy(both, lo, hi)


def _merge(intervals: list[tuple[float, float]]) -> list[tuple[float, float]]:
    out: list[tuple[float, float]] = []
    for a, b in sorted(intervals):
        if out and a <= out[-1][1] + 1e-9:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


def _refusal_rates(offers) -> list[dict]:
    rows = []
    for lo, hi in zip(REFUSAL_BINS[:-1], REFUSAL_BINS[1:], strict=True):
        inside = [o for o in offers if lo <= o.v_hat < hi or (hi == REFUSAL_BINS[-1] and o.v_hat >= hi)]
        refused = sum(o.refused for o in inside)
        rows.append({"v_hat_from": lo, "v_hat_to": hi, "offers": len(inside), "refusals": refused,
                     "rate": refused / len(inside) if inside else None})
    return rows


def _num(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def team_mode_metrics(runs: Sequence[SubjectRun], takt: float, robots: Sequence[str]) -> dict:
    """The team figures of one mode's ``runs`` (see the module docstring); ``robots``: the task's robots."""
    runs = sorted(runs, key=lambda r: r.subject)
    makespans, idle = [], {"human": 0.0, **dict.fromkeys(robots, 0.0)}
    both = 0.0
    overlapping = completed = 0
    paced_time = 0.0
    for run in runs:
        reps = [o for o in run.outcomes if o.outcome == "completed" and math.isfinite(o.t_end)]
        makespans.append([o.t_end - o.t_start for o in reps])
        completed += len(reps)
        if reps:
            paced_time += reps[-1].t_end - reps[0].t_start
        worker = _merge(_acting(run))
        spans = {r: _merge([(a, b) for name, a, b, _ in run.robot_spans if name == r]) for r in robots}
        for o in reps:
            span = o.t_end - o.t_start
            idle["human"] += span - _busy(worker, o.t_start, o.t_end)
            for r in robots:
                idle[r] += span - _busy(spans[r], o.t_start, o.t_end)
            robot_any = _merge([iv for r in robots for iv in spans[r]])
            both += _overlap(worker, robot_any, o.t_start, o.t_end)
            done = [a for a in run.allocations if a.repetition == o.repetition and a.done]
            overlapping += any(x.agent != y.agent and min(x.t_end, y.t_end) > max(x.t_start, y.t_start) + 1e-6
                               for i, x in enumerate(done) for y in done[i + 1:])
    total = sum(sum(m) for m in makespans)
    flat = [x for m in makespans for x in m]
    offers = [o for r in runs for o in r.offers]
    refused = [o for o in offers if o.refused]
    safety = [r.safety for r in runs if r.safety is not None]
    out = {
        "execution": runs[0].execution if runs else None,
        "makespan_s": makespans,
        "makespan_mean_s": float(np.mean(flat)) if flat else None,
        "makespan_median_s": float(np.median(flat)) if flat else None,
        "repetitions_completed": completed,
        "throughput_per_hour": 3600.0 * completed / total if total > 0 else None,
        "paced_throughput_per_hour": 3600.0 * completed / paced_time if paced_time > 0 else None,
        "takt_s": takt,
        "takt_overruns": sum(x > takt + 1e-9 for x in flat),
        "idle_s": idle,
        "idle_fraction": {k: v / total if total > 0 else None for k, v in idle.items()},
        "both_busy_s": both,
        "overlapping_repetitions": overlapping,
        "kwear_integral": float(np.mean([r.kwear_integral for r in runs])) if runs else None,
        "time_above_vth_s": float(np.mean([r.time_above_threshold for r in runs])) if runs else None,
        "offers": len(offers),
        "refusals": len(refused),
        "refusal_rate_by_v_hat": _refusal_rates(offers),
        "v_hat_refused_mean": float(np.mean([o.v_hat for o in refused])) if refused else None,
        "v_hat_accepted_mean": (float(np.mean([o.v_hat for o in offers if not o.refused]))
                                if len(refused) < len(offers) else None),
        "safety": None,
    }
    if safety:
        out["safety"] = {
            "ssm": any(s.scaled for s in safety),
            "min_separation_m": _num(min(s.min_separation for s in safety)),
            "robot_slowed_s": float(sum(sum(s.slowed.values()) for s in safety)),
            "robot_stopped_s": float(sum(sum(s.stopped.values()) for s in safety)),
            "overlap_s": float(sum(s.overlap for s in safety)),
            "overlap_moving_s": float(sum(s.overlap_moving for s in safety)),
            "end_separation_min_m": _num(min(s.end_separation for s in safety)),
            "params": safety[0].params,
        }
    return out


def team_document(cfg, runs_by_mode: Mapping[str, Sequence[SubjectRun]]) -> dict:
    """``team.json``: the team settings (execution, the cost weights used, negotiation) and each mode's
    :func:`team_mode_metrics`."""
    cost = cfg.cost
    settings = {**cfg.team_settings(), "gamma": cost.gamma, "v_th": cost.v_th, "robot_cost": cost.robot_cost}
    modes = {}
    for mode, runs in runs_by_mode.items():
        if runs:
            robots = sorted({r for run in runs for r in run.robots})
            modes[mode] = team_mode_metrics(runs, cfg.pacing.takt, robots)
    return {"settings": settings, "modes": modes}


def team_in_summary(cfg, runs_by_mode: Mapping[str, Sequence[SubjectRun]]) -> bool:
    """Whether the run writes ``team.json`` and ``summary.json`` carries the team figures: when a team
    setting departs from the paper's protocol or the robots were monitored. A paper protocol's outputs
    stay as they were (and its shards merge, :mod:`ergosim.experiment.run_merge`); :func:`team_document` gives
    the same figures of any runs in memory (``scripts/team_study.py`` for the sequential baseline)."""
    return "execution" in cfg.record() or any(r.safety is not None for runs in runs_by_mode.values()
                                             for r in runs)
