"""The Python API for experiments: load a scenario, change it, run it, read the results as objects.

>>> from ergosim import api
>>> sc = api.load("multi-subject", subjects=2, repetitions=2, modes=["hrc"],
...               overrides={"scene.l_xy": "0.20,0.82"})            # doctest: +SKIP
>>> res = api.run(sc, seed=0)                                       # doctest: +SKIP
>>> res.robot_share("hrc"), res.robot_share_by_action("hrc")        # doctest: +SKIP
>>> [a for a in res.allocations if a.agent == "robot"][:3]          # doctest: +SKIP

:func:`load` takes a bundled scenario's name or a scenario file (docs/workcell_format.md), protocol fields as
keywords and any other field by its ``--set`` dotted path in ``overrides``; everything is checked before
any physics, with the same one-line :class:`~ergosim.errors.ConfigError` the command line prints.
:func:`run` runs it exactly as ``ergosim run`` does (the same seed gives the same numbers, whatever
``jobs``) and returns :class:`Results`: the summary that ``summary.json`` holds, and every subject's runs
with their per-attempt :class:`~ergosim.twin.records.Allocation` records, failures, repetition outcomes
and per-tick ergonomics. The extension points (a scenario, a workcell, a mode, a risk index, an action
kind) are re-exported here as well. docs/api.md is the guide.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ergosim.experiment.frames import Frames, run_frames
from ergosim.experiment.protocol import ScenarioConfig
from ergosim.experiment.scenario import (
    Scenario,
    load_scenario,
    register_scenario,
    scenario_info,
    scenario_names,
)
from ergosim.experiment.scenario_check import precheck
from ergosim.experiment.scenario_run import run_scenario
from ergosim.experiment.subject import SubjectResult, subject_session
from ergosim.scenes import Workcell, build_cell, load_cell, register_scene, scene_names
from ergosim.scenes.action_kinds import ACTION_KINDS, ActionKind, register_action_kind
from ergosim.twin.modes import (
    IndexContext,
    Mode,
    RiskIndexEntry,
    get_mode,
    mode_names,
    register_mode,
    register_risk_index,
    risk_index_names,
)
from ergosim.twin.records import Allocation, Failure, RepetitionOutcome, SubjectRun
from ergosim.twin.session import Outcome, Session

__all__ = [
    "load",
    "run",
    "session",
    "workcell",
    "Results",
    "Frames",
    "Scenario",
    "ScenarioConfig",
    "SubjectResult",
    "SubjectRun",
    "Allocation",
    "Failure",
    "RepetitionOutcome",
    "Session",
    "Outcome",
    "Workcell",
    "scenario_names",
    "scenario_info",
    "scene_names",
    "mode_names",
    "risk_index_names",
    "register_scenario",
    "register_scene",
    "register_mode",
    "register_risk_index",
    "register_action_kind",
    "get_mode",
    "Mode",
    "RiskIndexEntry",
    "IndexContext",
    "ActionKind",
    "ACTION_KINDS",
]


def load(name_or_path: str | os.PathLike[str], overrides: Mapping[str, Any] | None = None,
         **protocol: Any) -> Scenario:
    """The checked :class:`~ergosim.experiment.scenario.Scenario` ``name_or_path`` (a registered name or a
    scenario file) with ``protocol`` fields set by keyword (``subjects=2``, ``modes=["hrc"]``,
    ``takt=40.0``) and ``overrides`` by ``--set`` key: a protocol field, ``scene.<dotted path or alias>`` of
    the workcell, ``task.<dotted path>`` of the task. Values may be typed or ``--set`` strings."""
    merged = dict(overrides or {})
    for key, value in protocol.items():
        if key in merged:
            raise TypeError(f"{key!r} given both as a keyword and in overrides")
        merged[key] = tuple(value) if isinstance(value, list) else value
    return load_scenario(name_or_path, merged or None)


@dataclasses.dataclass(frozen=True)
class Results:
    """What a run produced. ``summary``: the dict written to ``summary.json`` (docs/workcell_format.md and
    the README list its fields); ``subjects``: per subject, in order, its runs per mode
    (:class:`~ergosim.twin.records.SubjectRun`) and calibration; ``status``: ``complete``, ``abandoned``
    (a repetition could not be finished), ``interrupted``; ``out``: the folder with the files, or None."""

    scenario: str
    seed: int
    status: str
    summary: dict
    subjects: tuple[SubjectResult, ...]
    out: Path | None
    wall: float

    def runs(self, mode: str) -> list[SubjectRun]:
        """Every subject's run in ``mode``, in subject order."""
        self._mode(mode)
        return [s.runs[mode] for s in self.subjects if mode in s.runs]

    @property
    def allocations(self) -> list[Allocation]:
        """Every attempt of every subject in every mode (one row of ``allocations.csv`` each)."""
        return [a for s in self.subjects for run in s.runs.values() for a in run.allocations]

    @property
    def failures(self) -> list[Failure]:
        """Every failed attempt and abandoned repetition (``failures.csv``)."""
        return [f for s in self.subjects for run in s.runs.values() for f in run.failures]

    def frames(self) -> Frames:
        """The run's allocations, ticks and subjects as pandas DataFrames (``allocations``, ``ticks``,
        ``subjects``: the columns of allocations.csv, ticks.csv and subjects.csv). Needs the ``analysis``
        extra (``pip install 'ergosim[analysis]'``); without pandas, a one-line error says so."""
        return run_frames(self.subjects)

    def robot_share(self, mode: str) -> float:
        """Completed robot actions over completed actions either agent may do, in ``mode``."""
        return float(self._mode(mode)["robot_share"])

    def robot_share_by_action(self, mode: str) -> dict[str, float]:
        return dict(self._mode(mode)["robot_share_by_action"])

    def kwear_integral(self, mode: str) -> list[float]:
        """Per subject, ∫ΣV dt over the production schedule (repetitions × takt) [s]."""
        return list(self._mode(mode)["kwear_integral_by_subject"])

    def _mode(self, mode: str) -> dict:
        try:
            return self.summary["modes"][mode]
        except KeyError:
            raise KeyError(f"mode {mode!r} was not run; modes run: "
                           f"{', '.join(self.summary.get('modes', {}))}") from None


def run(scenario: Scenario | str | os.PathLike[str], *, seed: int = 0,
        out: str | os.PathLike[str] | None = None, jobs: int = 1, check: bool = True,
        progress: bool = False) -> Results:
    """Run ``scenario`` (a :class:`Scenario`, or a name or file loaded as it is) for its subjects and modes.

    ``out``: the folder for summary.json, the CSVs and the plots (the run owns it, as ``ergosim run
    --out``); None runs in a temporary folder that is removed afterwards (the results stay in memory).
    ``jobs``: processes (results do not depend on it). ``check``: refuse, before any subject starts, a run
    certain to fail (the reachability pre-check of ``ergosim run``)."""
    if not isinstance(scenario, Scenario):
        scenario = load(scenario)
    if seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    if check:
        precheck(scenario)
    if out is not None:
        res = run_scenario(scenario, seed=seed, out=Path(out), jobs=jobs, progress=progress)
        where: Path | None = Path(out)
    else:
        with tempfile.TemporaryDirectory(prefix="ergosim-") as tmp:
            res = run_scenario(scenario, seed=seed, out=Path(tmp) / scenario.name, jobs=jobs,
                               progress=progress, plots=False)  # nobody would see them
        where = None
    return Results(scenario.name, seed, res.status, res.summary, tuple(res.results), where, res.wall)


def session(scenario: Scenario | str | os.PathLike[str], mode: str, *, subject: int = 0, seed: int = 0,
            calibrate: bool = True) -> Session:
    """One subject's :class:`~ergosim.twin.session.Session` in ``mode``, to step by hand: ``run(n)``
    repetitions, or ``perform(action, agent)`` (an :class:`~ergosim.twin.session.Outcome`) one action at a
    time; ``session.cell`` is its :class:`~ergosim.scenes.Workcell`. See
    :func:`~ergosim.experiment.subject.subject_session` (built by :mod:`ergosim.twin.rig`)."""
    if not isinstance(scenario, Scenario):
        scenario = load(scenario)
    return subject_session(scenario, subject, seed, mode, calibrate=calibrate)


def workcell(name_or_path: str | os.PathLike[str], overrides: Mapping[str, Any] | None = None) -> Workcell:
    """The compiled :class:`~ergosim.scenes.Workcell` of a workcell (a registered name or a workcell file),
    with ``overrides`` by dotted path or alias (``{"parts.L.xy": "0.2,0.8"}``), checked first."""
    return build_cell(load_cell(name_or_path, **dict(overrides or {})))
