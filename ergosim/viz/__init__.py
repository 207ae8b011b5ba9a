"""Rerun visualisation of the twin: the 3-D workcell, joint angles, RULA and KWear traces, allocations.

Typical use (the twin loop)::

    rec = open_recording(rrd="run.rrd")          # or spawn=True, connect="default"; none -> no-op
    rec.log_static(cell.model, v_th=v_th, body_groups=groups)
    rec.log_ticks(rep, t, xpos, xquat, names, angles, rula_parts, rula_grand, kwear)   # per batch
    rec.log_decision(t_k, rep, v_now, v_hat, costs, chosen,
                     allocation_reason(chosen, v_hat=v_hat, costs=costs, v_th=v_th))
    rec.close()                                   # run.rrd is complete now
"""

from __future__ import annotations

from ergosim.quat import wxyz_to_xyzw
from ergosim.viz.blueprint import build_blueprint
from ergosim.viz.geometry import VISIBLE_GROUPS, SceneBody, Visual, default_body_groups, scene_bodies
from ergosim.viz.paths import GROUPS, body_entity
from ergosim.viz.readback import RecordingReader
from ergosim.viz.reason import REASONS, allocation_reason, reason_text, register_reason
from ergosim.viz.recorder import TwinRecorder
from ergosim.viz.sinks import DEFAULT_URL, SPAWN_PORT, SinkPlan, open_recording, plan_sinks

__all__ = [
    "TwinRecorder",
    "open_recording",
    "plan_sinks",
    "SinkPlan",
    "DEFAULT_URL",
    "SPAWN_PORT",
    "allocation_reason",
    "reason_text",
    "register_reason",
    "REASONS",
    "build_blueprint",
    "scene_bodies",
    "default_body_groups",
    "SceneBody",
    "Visual",
    "VISIBLE_GROUPS",
    "GROUPS",
    "body_entity",
    "wxyz_to_xyzw",
    "RecordingReader",
]
