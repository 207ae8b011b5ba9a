"""The protocol of a simulated experiment: what one session runs by, and what the experiment adds to it.

A scenario's ``[protocol]`` table and ``--set`` address every field by its flat name (``takt = 40``,
``--set subjects=3``). :class:`ScenarioConfig` holds the scenario's labels (``scene``, ``task``), the modes
it runs, the population its subjects are drawn from (:class:`PopulationConfig`) and the groups of one
session (:mod:`ergosim.twin.protocol`); :attr:`ScenarioConfig.session` is the part a session is built from
(:mod:`ergosim.twin.rig`). Flat names are unique across the groups; :data:`PROTOCOL_KEYS` lists them in
the order the file format documents them, :meth:`ScenarioConfig.record` writes them flat, as every output
records the protocol.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, Literal

from ergosim.errors import ConfigError
from ergosim.machine import physical_memory
from ergosim.overrides import flat_values, replace_flat
from ergosim.twin.modes import mode_names, mode_or_default
from ergosim.twin.protocol import (
    CalibrationConfig,
    CostConfig,
    LookaheadConfig,
    PacingConfig,
    RobotConfig,
    SensingConfig,
    SessionConfig,
    TeamConfig,
)
from ergosim.twin.records import TICK_COLUMNS
from ergosim.worker.subjects import Subject, make_subjects

__all__ = ["ScenarioConfig", "PopulationConfig", "PROTOCOL_KEYS", "SUBJECTS_MAX", "protocol_from_record",
           "run_memory"]

SUBJECTS_MAX = 10_000
"""Most subjects of one run (a study has tens; each keeps its records in memory until the run ends)."""
_TICK_BYTES_PER_COLUMN = 2 * 8
"""Memory per logged tick and column [bytes]: a float64, in a log that grows by doubling."""


def _need(ok: bool, msg: str, where: str) -> None:
    if not ok:
        raise ConfigError(msg, where=where)


@dataclasses.dataclass(frozen=True)
class PopulationConfig:
    """The synthetic subjects (:func:`ergosim.worker.subjects.make_subjects`)."""

    subjects: int = 1
    female_fraction: float = 2.0 / 12.0
    """Share of women among the synthetic subjects: §7.2's cohort, "2 females and 10 males"."""
    pace: float = 1.0
    """Mean pace of the subjects: 1 = MTM-1 standard performance (ergosim.worker.action_timing)."""

    def subject(self, index: int, seed: int) -> Subject:
        """Subject ``index`` of ``seed``'s population; it depends only on (seed, index)."""
        return make_subjects(index + 1, seed, female_fraction=self.female_fraction, pace=self.pace)[index]

    def validate(self, where: str) -> None:
        _need(1 <= self.subjects <= SUBJECTS_MAX,
              f"subjects must be in 1..{SUBJECTS_MAX}, got {self.subjects}", where)
        _need(0 <= self.female_fraction <= 1,
              f"female_fraction must be in [0, 1], got {self.female_fraction}", where)
        _need(0.1 <= self.pace <= 2.0, f"pace must be in [0.1, 2] (1 = MTM-1 standard performance), got "
              f"{self.pace}", where)


@dataclasses.dataclass(frozen=True)
class ScenarioConfig:
    """The protocol of one scenario. ``scene`` and ``task`` are labels (the workcell's name, the task file's
    name) for the outputs; ``modes``: the allocation modes run (:mod:`ergosim.twin.modes`);
    ``population``: who the subjects are. Every other field is a session's (:class:`SessionConfig`, in
    the same order)."""

    scene: str
    task: str
    modes: tuple[str, ...] = ("hrc",)
    planner: Literal["fast", "paper"] = "fast"
    tie_break: Literal["costliest-first", "task-order", "cheapest-first"] = "costliest-first"
    cost: CostConfig = CostConfig()
    robot: RobotConfig = RobotConfig()
    population: PopulationConfig = PopulationConfig()
    pacing: PacingConfig = PacingConfig()
    team: TeamConfig = TeamConfig()
    sensing: SensingConfig = SensingConfig()
    calibration: CalibrationConfig = CalibrationConfig()
    lookahead: LookaheadConfig = LookaheadConfig()

    @classmethod
    def of(cls, scene: str, task: str, **fields: Any) -> ScenarioConfig:
        """A protocol from flat field names: ``ScenarioConfig.of("cell", "task", takt=40.0,
        robot_cost=2.5)``."""
        return replace_flat(cls(scene, task), fields)

    def replace(self, **fields: Any) -> ScenarioConfig:
        """A copy with fields changed by their flat names (``cfg.replace(subjects=1, takt=45.0)``)."""
        return replace_flat(self, fields)

    @property
    def session(self) -> SessionConfig:
        """What one session of this protocol runs by (every field but the labels, modes and population)."""
        return SessionConfig(**{f.name: getattr(self, f.name) for f in dataclasses.fields(SessionConfig)})

    def validate(self, where: str = "scenario") -> None:
        self.population.validate(where)
        _need(all(m in mode_names() for m in self.modes) and len(self.modes) > 0,
              f"modes must be among {', '.join(mode_names())}, got {','.join(self.modes)}", where)
        self.session.validate(where)
        held, memory = run_memory(self), physical_memory()
        _need(held <= memory / 2, f"subjects × modes × repetitions × takt = {self.population.subjects} × "
              f"{len(self.modes)} × {self.pacing.repetitions} × {self.pacing.takt:g} s of records at "
              f"{self.sensing.ergonomics_rate:g} Hz need about {held / 1e9:.3g} GB in memory; this machine "
              f"has {memory / 1e9:.3g} GB (at most half of it is used)", where)

    def record(self) -> dict:
        """The protocol as the outputs record it (``summary.json`` ``config``, ``run.json``), flat by field
        name: every field, except the team group while it keeps its defaults, ``reba_threshold`` while it
        keeps its default, and the look-ahead's group while it keeps its defaults and no mode with its own
        allocator runs, so a paper protocol's outputs stay as they were."""
        out = flat_values(self)
        own_rule = any(mode_or_default(m).allocator is not None for m in self.modes)
        for group, default, used in ((self.team, TeamConfig(), False),
                                     (self.lookahead, LookaheadConfig(), own_rule)):
            if not used and group == default:
                for key in dataclasses.asdict(group):
                    out.pop(key)
        if self.cost.reba_threshold == CostConfig.reba_threshold:
            out.pop("reba_threshold")
        return out

    def team_settings(self) -> dict:
        """The team-execution fields and their values (``team.json``)."""
        return dataclasses.asdict(self.team)


PROTOCOL_KEYS: tuple[str, ...] = tuple(flat_values(ScenarioConfig("scene", "task")))
"""Every protocol key of a scenario file and of ``--set``, flat."""


def protocol_from_record(config: Mapping[str, Any]) -> ScenarioConfig:
    """The protocol a ``config`` of the outputs (:meth:`ScenarioConfig.record`, lists for tuples) holds."""
    fields = {k: tuple(v) if isinstance(v, list) else v for k, v in config.items()}
    return ScenarioConfig.of(fields.pop("scene"), fields.pop("task"), **fields)


def run_memory(cfg: ScenarioConfig) -> float:
    """Bytes a whole run of ``cfg`` holds in memory at its end: every subject's per-tick records of every
    mode over the schedule (repetitions × takt at the ergonomics rate)."""
    ticks = cfg.pacing.horizon * cfg.sensing.ergonomics_rate
    columns = len(TICK_COLUMNS) * _TICK_BYTES_PER_COLUMN
    return float(cfg.population.subjects) * len(cfg.modes) * ticks * columns
