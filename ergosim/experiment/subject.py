"""One subject of a scenario: who it is, the workcell built for its body, and its sessions.

The scenario chooses what is built (the population, the workcell, the task, the features its modes read:
:func:`rig_spec`); the twin builds it (:mod:`ergosim.twin.rig`). Every random draw of subject i comes from
``SeedSequence([seed, i])`` (:func:`ergosim.twin.rig.streams`), so a parallel run equals the serial run bit
for bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ergosim.ergonomics.kwear import KWearParams
from ergosim.experiment.scenario import Scenario
from ergosim.scenes import Workcell, build_cell
from ergosim.twin import rig
from ergosim.twin.modes import get_mode, get_risk_index
from ergosim.twin.records import SubjectRun
from ergosim.twin.session import Session
from ergosim.worker.subjects import Subject

__all__ = ["SubjectResult", "scenario_subject", "subject_cell", "scenario_features", "rig_spec",
           "calibrate_subject", "subject_session"]


@dataclasses.dataclass
class SubjectResult:
    """Runs per mode plus the subject's calibration figures."""

    subject: int
    name: str
    runs: dict[str, SubjectRun]
    eta: dict[str, int]
    calibration_errors: dict[str, float]
    alphas: dict[str, list[float]]
    rula_g: dict[str, float]
    traces: dict[str, tuple[np.ndarray, np.ndarray]] = dataclasses.field(default_factory=dict)
    """action -> (t (n,) [s], V (n, 5)): KWear from zero wear in the first calibration execution."""
    kwear_params: KWearParams = KWearParams()
    """The subject's KWear constants (C, r, ...; eq. 6-7)."""
    mtm: dict[str, str] = dataclasses.field(default_factory=dict)
    """action -> its MTM-1 analysis in the first calibration execution (ergosim.worker.action_timing)."""
    reba_g: dict[str, float] | None = None
    """action -> G(a_k) on REBA (the REBA score held longest), when a mode of the run reads REBA."""


def scenario_subject(scenario: Scenario, index: int, seed: int) -> Subject:
    """Subject ``index`` of ``seed``'s population, drawn as the scenario's protocol says (female fraction,
    pace); it depends only on (seed, index)."""
    return scenario.protocol.population.subject(index, seed)


def subject_cell(scenario: Scenario, subject: Subject) -> Workcell:
    """The scenario's workcell built for ``subject``'s body (the scenario's own overrides win)."""
    return build_cell(scenario.cell(**subject.workcell_fields))


def scenario_features(scenario: Scenario) -> tuple[str, ...]:
    """The posture features the scenario's modes read: ``rula`` always, then e.g. ``reba``."""
    extra = [get_risk_index(m.risk_index).features for m in map(get_mode, scenario.protocol.modes)
             if m.risk_index is not None]
    return tuple(dict.fromkeys(("rula", *extra)))


def rig_spec(scenario: Scenario) -> rig.RigSpec:
    """What the twin builds for the scenario's sessions: its session config, its workcell for a subject's
    body, its task and the features its modes read."""
    return rig.RigSpec(scenario.protocol.session, lambda subject: subject_cell(scenario, subject),
                       scenario.task, scenario_features(scenario))


def calibrate_subject(scenario: Scenario, index: int, seed: int, subject: Subject | None = None):
    """Subject ``index`` of ``seed``'s population calibrated in the scenario's workcell, as its run does
    (§5, from child 0 of ``SeedSequence([seed, index])``): (subject, calibration, the worker's expected
    seconds per action). ``subject``: that subject with some fields changed (a what-if, e.g. its
    trial-to-trial variability), calibrated on the same random stream; default the subject as drawn."""
    subject = scenario_subject(scenario, index, seed) if subject is None else subject
    return rig.calibrated(rig_spec(scenario), subject, index, seed)


def subject_session(scenario: Scenario, index: int, seed: int, mode: str, *, calibrate: bool = True,
                    record_bodies: bool = False, calibrated=None) -> Session:
    """A ready :class:`Session` of subject ``index`` of ``seed``'s population in ``mode``, for stepping by
    hand: ``session.run(n)`` repetitions, or ``session.perform(action, agent)`` one action at a time.

    ``calibrate``: calibrate the subject first (§5), as a run does; a mode without a risk index (``h-only``,
    ``r-only``) may skip it; ``calibrated``: what :func:`calibrate_subject` returned for the same subject
    (not calibrated again). Draws from ``SeedSequence([seed, index])`` like the subject's run, whose first
    mode it then equals."""
    return rig.ready_session(rig_spec(scenario), scenario_subject(scenario, index, seed), index, seed, mode,
                             calibrate=calibrate, record_bodies=record_bodies, calibrated_as=calibrated)
