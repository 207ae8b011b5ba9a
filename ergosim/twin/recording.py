"""Log a finished subject run to rerun: scene geometry, per-tick bodies and ergonomics, decisions.

The loop records body poses at the ergonomics rate alongside the tick log (the same rows), so a run can
be logged after it finished, in the main process, also when subjects ran in parallel processes.
"""

from __future__ import annotations

import numpy as np

from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import TICK_COLUMNS, SubjectRun
from ergosim.viz import TwinRecorder, default_body_groups

__all__ = ["record_run"]

_ANGLES = slice(TICK_COLUMNS.index("trunk_flexion"), TICK_COLUMNS.index("wrist_deviation") + 1)
_RULA = slice(TICK_COLUMNS.index("rula_upper_arm"), TICK_COLUMNS.index("rula_legs") + 1)
_GRAND = TICK_COLUMNS.index("rula_grand")


def record_run(recorder: TwinRecorder, model, run: SubjectRun, v_th: float, parts: tuple[str, ...]) -> None:
    """Log ``run`` (which must carry ``bodies``) with the workcell ``model`` it ran in (its ``parts``)."""
    if not recorder.enabled or run.bodies is None:
        return
    recorder.log_static(model, v_th=np.full(len(KWEAR_JOINTS), v_th),
                        body_groups=default_body_groups(model, parts))
    names = tuple(model.body(b).name for b in range(model.nbody))
    rows, (pos, quat) = run.ticks.rows, run.bodies
    for rep in np.unique(rows[:, 0]).astype(int):
        sel = rows[:, 0] == rep
        r = rows[sel]
        recorder.log_ticks(int(rep), r[:, 1], pos[sel], quat[sel], names, r[:, _ANGLES], r[:, _RULA],
                           r[:, _GRAND], run.ticks.kwear[sel])
    for d in run.decisions:
        recorder.log_decision(d.time, d.repetition, d.v_now, d.v_hat, d.costs, (d.action, d.agent), d.reason)
    for f in run.failures:  # failed attempts and abandoned repetitions, beside the decisions
        recorder.log_event(f.time, f.repetition, f"{f.status}: {f.message}", level="WARN")
