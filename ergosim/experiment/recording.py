"""Log a finished subject run to rerun: scene geometry, per-tick bodies and ergonomics, decisions.

The loop records body poses at the ergonomics rate alongside the tick log (the same rows), so a run can
be logged after it finished, in the main process, also when subjects ran in parallel processes.
"""

from __future__ import annotations

import numpy as np

from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import TICK_COLUMNS, SubjectRun
from ergosim.viz import TwinRecorder, default_body_groups, reason_text

__all__ = ["record_run"]

_ANGLES = slice(TICK_COLUMNS.index("trunk_flexion"), TICK_COLUMNS.index("wrist_deviation") + 1)
_RULA = slice(TICK_COLUMNS.index("rula_upper_arm"), TICK_COLUMNS.index("rula_legs") + 1)
_GRAND = TICK_COLUMNS.index("rula_grand")
_REPETITION_COLOR = (120, 120, 120)  # grey: the frame of the story, not an event in it
_REFUSAL_COLOR = (170, 90, 200)  # purple: the worker said no


def record_run(recorder: TwinRecorder, model, run: SubjectRun, v_th: float, parts: tuple[str, ...],
               view: tuple[float, float] | None = None) -> None:
    """Log ``run`` (which must carry ``bodies``) with the workcell ``model`` it ran in (its ``parts``);
    ``view``: (azimuth, elevation) [deg] of the workcell's camera view, for the 3-D view's start."""
    if not recorder.enabled or run.bodies is None:
        return
    costs = [c for d in run.decisions for c in d.costs.values() if np.isfinite(c)]
    recorder.log_static(model, v_th=np.full(len(KWEAR_JOINTS), v_th),
                        body_groups=default_body_groups(model, parts), view=view,
                        max_cost=max(costs) if costs else None)
    names = tuple(model.body(b).name for b in range(model.nbody))
    rows, (pos, quat) = run.ticks.rows, run.bodies
    for rep in np.unique(rows[:, 0]).astype(int):
        sel = rows[:, 0] == rep
        r = rows[sel]
        recorder.log_ticks(int(rep), r[:, 1], pos[sel], quat[sel], names, r[:, _ANGLES], r[:, _RULA],
                           r[:, _GRAND], run.ticks.kwear[sel])
    _log_repetitions(recorder, run)  # first: at equal times the log keeps this order
    for d in run.decisions:
        recorder.log_decision(d.time, d.repetition, d.v_now, d.v_hat, d.costs, (d.action, d.agent),
                              reason_text(d))
    for f in run.failures:  # failed attempts and abandoned repetitions, beside the decisions
        recorder.log_event(f.time, f.repetition, f"{f.status}: {f.message}", level="WARN")
    for o in run.offers:  # negotiation: the worker's refusals, each before the re-planned decision
        if o.refused:
            recorder.log_event(o.time, o.repetition, f"refused: {o.message}", level="INFO",
                               color=_REFUSAL_COLOR)


def _log_repetitions(recorder: TwinRecorder, run: SubjectRun) -> None:
    """Where each repetition starts and how it ended, as grey lines between the decisions (an abandoned
    repetition as a warning)."""
    takt = run.horizon / len(run.outcomes) if run.outcomes and np.isfinite(run.horizon) else None
    for o in run.outcomes:
        if not np.isfinite(o.t_start):
            continue
        recorder.log_event(o.t_start, o.repetition, f"repetition {o.repetition} starts", level="INFO",
                           color=_REPETITION_COLOR)
        took = o.t_end - o.t_start
        text = f"repetition {o.repetition} {o.outcome} after {took:.1f} s"
        if takt is not None and took > takt + 1e-9:
            text += f", over the takt of {takt:g} s"
        if o.reason:
            text += f": {o.reason}"
        ok = o.outcome == "completed"
        recorder.log_event(o.t_end, o.repetition, text, level="INFO" if ok else "WARN",
                           color=_REPETITION_COLOR if ok else None)
