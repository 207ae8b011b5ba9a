"""The figures of one subject's run in one mode, as the columns of a sweep's ``results.parquet``.

They are the per-subject figures of ``summary.json`` (:func:`~ergosim.experiment.summary.summarise`), computed
by the same code from a :class:`~ergosim.experiment.subject_records.RunRecord`, so a sweep unit and the same
subject in ``ergosim run`` agree. Per-action metrics are named ``<metric>.<action>``
(``robot_share.a1``, ``rula_g.a1``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from ergosim.errors import ConfigError
from ergosim.experiment.summary import summarise

__all__ = ["METRICS", "ACTION_METRICS", "DEFAULT_METRICS", "INTEGER_METRICS", "metric_columns",
           "check_metric", "unit_metrics", "metric_label"]

METRICS: dict[str, str] = {
    "robot_share": "robot share: completed robot actions / completed actions either agent may do",
    "robot_share_chosen": "robot share of the decisions where both agents could be chosen",
    "kwear_integral": "KWear integral ∫ΣV dt over repetitions × takt [s]",
    "kwear_integral_run": "KWear integral over the whole run [s]",
    "kwear_mean": "mean ΣV over the run",
    "time_above_vth": "time with some joint at V ≥ V_th [s]",
    "takt_overruns": "repetitions over the takt",
    "duration": "simulated duration of the run [s]",
    "repetitions_completed": "repetitions completed",
    "repetitions_abandoned": "repetitions abandoned",
    "actions": "completed actions either agent may do",
    "robot_actions": "of those, completed by the robot",
    "forced_robot_actions": "robot actions forced by failures",
    "forced_human_actions": "worker actions forced by failures",
    "failed_attempts": "failed attempts",
    "robot_failures": "robot failures",
    "worker_failures": "worker failures",
    "first_robot_repetition": "the first repetition in which the robot completed an action (none: never)",
    "first_robot_time": "when the robot started the first action it completed [s from the run's start]",
}
"""Metric name -> what it is [unit]: one number per (cell, subject, mode, seed)."""

ACTION_METRICS: dict[str, str] = {
    "robot_share": "share of {a} completed by the robot",
    "rula_g": "G({a}): the action's RULA grand score (calibration, §7.1)",
}
"""Per-action metrics, columns ``<name>.<action>``."""

INTEGER_METRICS = frozenset({"takt_overruns", "repetitions_completed", "repetitions_abandoned", "actions",
                             "robot_actions", "forced_robot_actions", "forced_human_actions",
                             "failed_attempts", "robot_failures", "worker_failures",
                             "first_robot_repetition"})

DEFAULT_METRICS = ("robot_share", "kwear_integral", "time_above_vth", "takt_overruns")


def metric_columns(actions: Sequence[str]) -> list[str]:
    """Every metric column for a task with ``actions``, in the order of the results table."""
    cols = ["robot_share", *(f"robot_share.{a}" for a in actions)]
    cols += [m for m in METRICS if m != "robot_share"]
    cols += [f"rula_g.{a}" for a in actions]
    return cols


def check_metric(name: str, actions: Sequence[str], where: str) -> str:
    if name in metric_columns(actions):
        return name
    head, _, action = name.partition(".")
    if head in ACTION_METRICS and action:
        raise ConfigError(f"unknown action {action!r} in metric {name!r}; the task's actions: "
                          f"{', '.join(actions)}", where=where)
    raise ConfigError(f"unknown metric {name!r}; valid metrics: {', '.join(METRICS)}, or "
                      f"{', '.join(f'{m}.<action>' for m in ACTION_METRICS)}", where=where)


def metric_label(name: str) -> str:
    """Axis label of a metric for plots."""
    head, _, action = name.partition(".")
    if action and head in ACTION_METRICS:
        return ACTION_METRICS[head].format(a=action)
    return METRICS.get(name, name)


def unit_metrics(run, rula_g: Mapping[str, float], actions: Sequence[str]) -> dict[str, float | int | None]:
    """The metrics of ``run`` (a RunRecord or SubjectRun) with the subject's G(a_k) ``rula_g``. A share is
    None when there is nothing to share (no completed action either agent may do)."""
    m = summarise("", 0, {run.mode: [run]}, actions=actions)["modes"][run.mode]
    shared = m["actions"] > 0
    out: dict[str, float | int | None] = {"robot_share": m["robot_share"] if shared else None}
    for a in actions:
        out[f"robot_share.{a}"] = m["robot_share_by_action"].get(a)
    out["robot_share_chosen"] = m["robot_share_chosen"] if m["choices"] else None
    out["kwear_integral"] = m["kwear_integral_by_subject"][0]
    out["kwear_integral_run"] = m["kwear_integral_run_by_subject"][0]
    out["kwear_mean"] = m["kwear_mean_by_subject"][0]
    out["time_above_vth"] = m["time_above_vth_by_subject"][0]
    out["takt_overruns"] = m["takt_overruns"]
    out["duration"] = m["duration_by_subject"][0]
    for key in ("repetitions_completed", "repetitions_abandoned", "actions", "robot_actions",
                "forced_robot_actions", "forced_human_actions", "failed_attempts", "robot_failures",
                "worker_failures"):
        out[key] = int(m[key])
    robot = sorted((a.repetition, a.t_start) for a in run.allocations if a.done and run.by_robot(a.agent))
    out["first_robot_repetition"] = int(robot[0][0]) if robot else None
    out["first_robot_time"] = float(robot[0][1]) if robot else None
    for a in actions:
        g = rula_g.get(a)
        out[f"rula_g.{a}"] = float(g) if g is not None else None
    return out
