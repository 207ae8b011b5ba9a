"""Run one subject of a scenario: calibrate it in the workcell, then every mode's repetitions.

Subjects are independent jobs (``--jobs`` runs them in parallel processes). The sessions are built by the
twin's rig (:mod:`ergosim.twin.rig`) from the scenario's spec (:func:`~ergosim.experiment.subject.rig_spec`).
"""

from __future__ import annotations

import logging

import numpy as np

from ergosim.experiment.scenario import Scenario
from ergosim.experiment.subject import SubjectResult, rig_spec, scenario_subject
from ergosim.twin import rig
from ergosim.twin.records import SubjectRun

__all__ = ["run_subject"]

log = logging.getLogger(__name__)


def run_subject(scenario: Scenario, index: int, seed: int, modes: tuple[str, ...],
                record_mode: str | tuple[str, ...] | None = None,
                slots: tuple[int, ...] | None = None) -> SubjectResult:
    """Calibrate subject ``index`` of ``seed``'s population, then run each mode from zero wear.

    ``record_mode``: keep body poses per tick for that mode's run, or those modes' runs (for the rerun
    recording and the video); copying the poses changes nothing in the simulation. ``slots``: the random
    stream of each mode, its position in the run's mode list (default ``0, 1, ...``): the calibration
    draws from child 0 of ``SeedSequence([seed, index])`` and mode slot k from child 1 + k, so one mode
    run alone with its slot (a sweep's work unit) equals that mode in the whole run."""
    cfg = scenario.protocol
    spec = rig_spec(scenario)
    recorded = {record_mode} if isinstance(record_mode, str) else set(record_mode or ())
    subject = scenario_subject(scenario, index, seed)
    slots = tuple(range(len(modes))) if slots is None else tuple(slots)
    seqs = rig.streams(seed, index, slots)
    calibrations, traces, mtm, seconds = rig.calibrate(spec, subject, np.random.default_rng(seqs[0]))
    log.debug("subject %d (%s): calibrated, η %s", index, subject.name, dict(calibrations["rula"].eta))
    runs: dict[str, SubjectRun] = {}
    for mode, seq in zip(modes, seqs[1:], strict=True):
        session = rig.build_session(spec, subject, mode, np.random.default_rng(seq), calibrations,
                                    index=index, record_bodies=mode in recorded, seed=seed,
                                    human_seconds=seconds)
        runs[mode] = session.run(cfg.pacing.repetitions)
        runs[mode].calibration_eta = calibrations[rig.feature_of(mode)].eta
    calibration = calibrations["rula"]
    reba = calibrations.get("reba")
    return SubjectResult(
        subject=index, name=subject.name, runs=runs, eta=calibration.eta,
        calibration_errors={a: float(c.max_error.max()) for a, c in calibration.actions.items()},
        alphas={a: [float(x) for x in c.alpha] for a, c in calibration.actions.items()},
        rula_g={a: float(c.rula_grand) for a, c in calibration.actions.items()},
        traces=traces, kwear_params=subject.kwear_params(), mtm=mtm,
        reba_g=None if reba is None else {a: float(c.rula_grand) for a, c in reba.actions.items()},
    )
