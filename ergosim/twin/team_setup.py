"""What a run adds to a session beyond the paper's loop, from the protocol and the workcell: the time term of
the costs, negotiation, speed and separation monitoring, and which session runs (sequential or parallel).

Everything here is off in the paper's protocol (``execution = "sequential"``, ``w_time = 0``, negotiation
off, the workcell's ``[safety] ssm = "auto"``), so a paper run is the paper's loop exactly.
"""

from __future__ import annotations

import zlib

import numpy as np

from ergosim.twin.negotiation import Negotiator
from ergosim.twin.session import Session
from ergosim.twin.ssm_monitor import SafetyMonitor
from ergosim.twin.team_session import ParallelExecution
from ergosim.worker.refusal import RefusalModel

__all__ = ["NEGOTIATION_STREAM", "refusal_model", "make_session"]

NEGOTIATION_STREAM = 1017
"""Entropy word that keeps the negotiation's random stream apart from the subject's others: a subject's
tolerance comes from ``SeedSequence([seed, subject, 1017])``, the offers of a mode from ``[..., 1017,
crc32(mode)]``, so negotiation never changes the draws of the motion, the mocap or the calibration."""


def refusal_model(cfg, seed: int, subject: int) -> RefusalModel:
    """Subject ``subject``'s refusal curve under protocol ``cfg`` (the same in every mode)."""
    rng = np.random.default_rng(np.random.SeedSequence([seed, subject, NEGOTIATION_STREAM]))
    return RefusalModel.for_subject(rng, mean=cfg.team.refusal_tolerance, sd=cfg.team.refusal_tolerance_sd,
                                    slope=cfg.team.refusal_slope)


def make_session(cfg, *, rig, allocator, mode: str, subject: int, seed: int, rng: np.random.Generator,
                 human_seconds: dict[str, float] | None = None) -> Session:
    """The session of one subject in one mode: with the parallel strategy
    (:class:`~ergosim.twin.team_session.ParallelExecution`) for ``execution = "parallel"``, else the
    sequential one, with the protocol's time term, negotiation and the workcell's monitoring."""
    plant = rig.plant
    allocator.prepare(cfg=cfg, cell=rig.cell, robots=rig.robots, human_seconds=human_seconds or {})
    negotiator = None
    if cfg.team.negotiation:
        offers = np.random.default_rng(np.random.SeedSequence([seed, subject, NEGOTIATION_STREAM,
                                                               zlib.crc32(mode.encode())]))
        negotiator = Negotiator(refusal_model(cfg, seed, subject), plant.kwear, offers)
    safety, monitor = rig.cell.config.safety, None
    if rig.robots and (cfg.team.execution == "parallel" or safety.ssm == "on"):
        monitor = SafetyMonitor(rig.cell, rig.robots, safety, scale=safety.enabled(cfg.team.execution),
                                every=plant.tick_every, dt_control=plant.dt_control)
        plant.hooks.append(monitor)
    kwargs = dict(cfg=cfg, mode=mode, subject_index=subject, worker=rig.worker, plant=plant, robot=rig.robots,
                  allocator=allocator, rng=rng, negotiator=negotiator, monitor=monitor)
    if cfg.team.execution == "parallel":
        kwargs["strategy"] = ParallelExecution(margin=cfg.team.team_margin)
    return Session(**kwargs)
