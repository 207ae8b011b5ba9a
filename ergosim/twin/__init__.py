"""The simulation: one subject's repetitions in one mode, tick by tick (paper Fig. 1).

A session is built in one place (:mod:`~ergosim.twin.rig`) from its config (:mod:`~ergosim.twin.protocol`):
the plant steps the workcell and the per-tick ergonomics (:mod:`~ergosim.twin.loop`), the tracks drive the
worker and the robots (:mod:`~ergosim.twin.worker_track`, :mod:`~ergosim.twin.robot_track`), the allocator
decides (:mod:`~ergosim.twin.allocator`, :mod:`~ergosim.twin.modes`, the bundled modes in
:mod:`~ergosim.twin.catalogue`) and the session runs the repetitions (:mod:`~ergosim.twin.session`) with
its execution strategy (:mod:`~ergosim.twin.sequential`, or parallel team execution in
:mod:`~ergosim.twin.team_session`). What it produces (:mod:`~ergosim.twin.records`) is plain data.
Nothing here knows about scenario files, output folders, plots or videos (:mod:`ergosim.experiment`).

Names are imported on first use, so ``import ergosim.twin`` stays cheap.
"""

from __future__ import annotations

from ergosim.exports import lazy_exports

_EXPORTS = {
    "Plant": "loop", "Session": "session", "Outcome": "session", "ParallelExecution": "team_session",
    "SequentialExecution": "sequential",
    "Allocator": "allocator", "Decision": "allocator",
    "Mode": "modes", "RiskIndexEntry": "modes", "IndexContext": "modes", "register_mode": "modes",
    "register_risk_index": "modes", "get_mode": "modes", "mode_names": "modes", "risk_index_names": "modes",
    "SessionConfig": "protocol", "RigSpec": "rig", "Rig": "rig",
    "SubjectRun": "records", "Allocation": "records", "Failure": "records", "RepetitionOutcome": "records",
    "TickLog": "records", "TICK_COLUMNS": "records",
    "WorkerTrack": "worker_track", "RobotTrack": "robot_track", "SceneCalibration": "calibration",
    "SafetyMonitor": "ssm_monitor",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
