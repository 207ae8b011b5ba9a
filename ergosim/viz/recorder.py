"""TwinRecorder: what the twin loop logs to rerun, in batches of ticks and at each allocation decision.

History goes in columns (``send_columns``): rows are buffered (:mod:`ergosim.viz.columns`) and sent with one
call per entity every ``flush_ticks`` ticks and at close, never one call per tick, however the loop batches
them. Every row is indexed on the ``sim_time`` timeline (seconds of simulated time) and the ``repetition``
sequence.
Non-finite samples (motion-capture dropouts) are left out of the series, so a plot shows a gap in the
samples rather than a made-up value. A recorder built without a stream is a no-op, so the loop calls it
unconditionally.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import mujoco
import numpy as np
import rerun as rr

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.errors import RecordingError
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS
from ergosim.quat import wxyz_to_xyzw
from ergosim.viz import paths, styles
from ergosim.viz.blueprint import build_blueprint
from ergosim.viz.columns import ColumnBuffer
from ergosim.viz.eye import frame_scene
from ergosim.viz.geometry import SceneBody, scene_bodies
from ergosim.viz.paths import join
from ergosim.viz.scene import log_scene

__all__ = ["TwinRecorder"]

_M = len(KWEAR_JOINTS)
_EVENT_COLOR = (230, 126, 34)  # orange: a failure stands out among the agents' blue and red decisions
_FLUSH_TIMEOUT = 20.0
"""Seconds :meth:`TwinRecorder.close` waits for a viewer to take the recording (assumed: a local viewer
takes a whole run in well under a second; a dead URL must not hang the run)."""


class TwinRecorder:
    """Logs one twin run. ``stream`` None gives a recorder whose methods do nothing (``enabled`` False).

    ``on_close(commit)`` runs after the stream is flushed and disconnected, e.g. to move a finished .rrd
    file into place (commit True) or drop it (commit False, an exception inside a ``with`` block).
    """

    def __init__(self, stream: rr.RecordingStream | None = None, *,
                 on_close: Callable[[bool], None] | None = None, flush_ticks: int = 1024) -> None:
        self._stream = stream
        self.flush_ticks = flush_ticks
        self._buffer = ColumnBuffer()
        self._pending = 0
        self._span: tuple[tuple[float, int], tuple[float, int]] | None = None
        self._on_close = on_close
        if stream is not None:
            # only simulated time means anything here; wall-clock log_time would make recordings differ
            stream.set_log_time_enabled(False)
            stream.set_log_tick_enabled(False)
        self._bodies: tuple[SceneBody, ...] = ()
        self._v_th = np.full(_M, np.nan)
        self._tick_index: tuple[tuple[str, ...], list[tuple[int, str]]] = ((), [])
        self._styled: set[str] = set()

    @property
    def enabled(self) -> bool:
        return self._stream is not None

    @property
    def body_entities(self) -> dict[str, str]:
        """Body name -> entity path, as set by :meth:`log_static`."""
        return {b.name: b.entity for b in self._bodies}

    # -- once -----------------------------------------------------------------------------------------------
    def log_static(self, model: mujoco.MjModel, *, v_th: np.ndarray, body_groups: Mapping[str, str],
                   view: tuple[float, float] | None = None, max_cost: float | None = None) -> None:
        """Scene geometry, series styles and the KWear thresholds ``v_th`` (5,) in KWEAR_JOINTS order.

        ``body_groups``: body name -> robot | human | parts | scene (bodies left out are scene). ``view``:
        (azimuth, elevation) [deg] the 3-D view looks from (the workcell's camera view), framing every
        visible geom (:func:`~ergosim.viz.eye.frame_scene`); the blueprint is sent again with that eye.
        ``max_cost``: the largest hyper-arc cost the recording will hold, which scales the costs' plot.
        """
        v_th = np.asarray(v_th, dtype=float)
        if v_th.shape != (_M,):
            raise ValueError(f"v_th must have shape ({_M},), got {v_th.shape}")
        self._v_th = v_th.copy()
        self._bodies = scene_bodies(model, body_groups)
        if self._stream is None:
            return
        s = self._stream
        s.log(paths.WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        log_scene(s, self._bodies)
        self._series_static()
        scaled = max_cost is not None and np.isfinite(max_cost) and max_cost > 0
        costs = (0.0, 1.1 * max_cost) if scaled else None
        s.send_blueprint(build_blueprint(frame_scene(model, *(view or ())), cost_range=costs))

    def log_ergonomics_static(self, *, v_th: np.ndarray) -> None:
        """Series styles and the KWear thresholds ``v_th`` (5,) for a recording without a scene (a replayed
        motion capture): then :meth:`log_ticks` takes zero bodies."""
        v_th = np.asarray(v_th, dtype=float)
        if v_th.shape != (_M,):
            raise ValueError(f"v_th must have shape ({_M},), got {v_th.shape}")
        self._v_th = v_th.copy()
        self._scene_free = True
        if self._stream is not None:
            self._series_static()

    @property
    def _one_threshold(self) -> bool:
        """Every joint has the same V_th: one line, ``ergonomics/kwear_threshold``, instead of five."""
        return bool(np.all(self._v_th == self._v_th[0]))

    def _series_static(self) -> None:
        s = self._stream
        if self._one_threshold:
            s.log(paths.KWEAR_THRESHOLD, styles.threshold_style(None), static=True)
        for joint in KWEAR_JOINTS:
            s.log(join(paths.KWEAR, joint), styles.kwear_style(joint), static=True)
            if not self._one_threshold:
                s.log(join(paths.KWEAR_THRESHOLD, joint), styles.threshold_style(joint), static=True)
            s.log(join(paths.V_NOW, joint), styles.decision_style(f"V {joint}", styles.JOINT_COLORS[joint]),
                  static=True)
        for part in (*RULA_PARTS, "grand"):
            s.log(join(paths.RULA, part), styles.rula_style(part), static=True)
        for name in ANGLE_NAMES:
            s.log(join(paths.ANGLES, name), styles.angle_style(name), static=True)

    # -- per batch of ticks ---------------------------------------------------------------------------------
    def log_ticks(self, repetition: int, sim_time: np.ndarray, body_pos: np.ndarray,
                  body_quat_wxyz: np.ndarray, body_names: Sequence[str], angles: np.ndarray,
                  rula_parts: np.ndarray, rula_grand: np.ndarray, kwear: np.ndarray) -> None:
        """A batch of n ticks of one repetition (copied: the caller may reuse its buffers).

        ``sim_time`` (n,) [s]; ``body_pos`` (n, b, 3) world frame [m]; ``body_quat_wxyz`` (n, b, 4) world
        frame, MuJoCo order; ``body_names`` (b,) names the columns; ``angles`` (n, 14) [deg] in ANGLE_NAMES
        order; ``rula_parts`` (n, 7) in RULA_PARTS order; ``rula_grand`` (n,); ``kwear`` (n, 5) in
        KWEAR_JOINTS order. Rows are sent once ``flush_ticks`` have accumulated, and at :meth:`flush`.
        """
        if self._stream is None:
            return
        t = np.array(sim_time, dtype=float)  # our copy: shared by every entity with no missing sample
        n = t.shape[0]
        nb = len(body_names)
        pos = np.asarray(body_pos, dtype=np.float32)
        _check("body_pos", pos, (n, nb, 3))
        _check("body_quat_wxyz", np.asarray(body_quat_wxyz), (n, nb, 4))
        series = (
            (paths.ANGLES, ANGLE_NAMES, _checked("angles", angles, (n, len(ANGLE_NAMES)))),
            (paths.RULA, RULA_PARTS, _checked("rula_parts", rula_parts, (n, len(RULA_PARTS)))),
            (paths.RULA, ("grand",), _checked("rula_grand", rula_grand, (n,))[:, None]),
            (paths.KWEAR, KWEAR_JOINTS, _checked("kwear", kwear, (n, _M))),
        )
        moving = self._moving_bodies(tuple(body_names))
        if n == 0:
            return
        rep = np.full(n, int(repetition), dtype=np.int64)
        quat = wxyz_to_xyzw(body_quat_wxyz)
        finite = np.isfinite(pos).all(axis=-1) & np.isfinite(quat).all(axis=-1)
        buf = self._buffer
        for col, entity in moving:
            rows = finite[:, col]  # boolean indexing copies, so nothing aliases the caller's arrays
            buf.poses(entity, *self._times(t, rep, rows), pos[rows, col], quat[rows, col])
        for prefix, names, values in series:
            ok = np.isfinite(values)
            for j, name in enumerate(names):
                rows = ok[:, j]
                buf.scalars(join(prefix, name), *self._times(t, rep, rows), values[rows, j])
        first = self._span[0] if self._span else (t[0], rep[0])
        self._span = (first, (t[-1], rep[-1]))
        self._pending += n
        if self._pending >= self.flush_ticks:
            self.flush()

    @staticmethod
    def _times(t: np.ndarray, rep: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return (t, rep) if rows.all() else (t[rows], rep[rows])

    def _moving_bodies(self, body_names: tuple[str, ...]) -> list[tuple[int, str]]:
        """(column, entity) of the bodies whose pose is logged per tick (world-welded ones are static)."""
        if not body_names and getattr(self, "_scene_free", False):
            return []
        if self._tick_index[0] != body_names:
            if not self._bodies:
                raise RuntimeError("log_static must be called before log_ticks")
            known = {b.name: b for b in self._bodies}
            # an unnamed body is "body<id>" (scene_bodies), which is its column when all bodies are given
            names = [n or f"body{c}" for c, n in enumerate(body_names)]
            missing = [n for n in names if n not in known]
            if missing:
                raise ValueError(f"log_ticks got bodies the model does not have: {', '.join(missing)}")
            index = [(c, known[n].entity) for c, n in enumerate(names) if known[n].static_pose is None]
            self._tick_index = (body_names, index)
        return self._tick_index[1]

    # -- per decision ---------------------------------------------------------------------------------------
    def log_decision(self, sim_time: float, repetition: int, v_now: np.ndarray,
                     v_hat: Mapping[str, np.ndarray], costs: Mapping[tuple[str, str], float],
                     chosen: tuple[str, str], reason: str) -> None:
        """One allocation decision at ``sim_time`` [s]: V(t_k) ``v_now`` (5,), the predicted V̂(t_k+1) per
        candidate action ``v_hat`` (action -> (5,)), the candidates' hyper-arc ``costs`` ((action, agent)
        -> cost), and the ``chosen`` (action, agent) with the ``reason`` (see :func:`allocation_reason`).
        Sent with the next flush of ticks."""
        if self._stream is None:
            return
        t, rep = np.array([float(sim_time)]), np.array([int(repetition)])
        buf = self._buffer
        color = styles.agent_color(chosen[1])
        buf.text(paths.ALLOCATION_LOG, float(sim_time), int(repetition), reason, color)
        for j, joint in enumerate(KWEAR_JOINTS):
            buf.scalars(join(paths.V_NOW, joint), t, rep, np.array([float(v_now[j])]))
        for action, predicted in v_hat.items():
            values = np.atleast_1d(np.asarray(predicted, dtype=float))
            # KWear predicts one V̂ per joint; a static index (the RULA baseline) one normalised score
            names = KWEAR_JOINTS if len(values) == len(KWEAR_JOINTS) else ("score",) * len(values)
            for joint, value in zip(names, values, strict=True):
                entity = join(paths.V_HAT, action, joint)
                self._style(entity, f"{action} {joint}", styles.JOINT_COLORS.get(joint, styles.PALETTE[7]))
                buf.scalars(entity, t, rep, np.array([float(value)]))
        for (action, agent), cost in costs.items():
            entity = join(paths.COSTS, action, agent)
            self._style(entity, f"{action} {agent}", styles.agent_color(agent))
            buf.scalars(entity, t, rep, np.array([float(cost)]))

    def log_event(self, sim_time: float, repetition: int, text: str, level: str = "WARN",
                  color: tuple[int, int, int] | None = None) -> None:
        """A line in the allocation text log at ``sim_time`` [s], e.g. a failed attempt (``level`` WARN, in
        orange) or a repetition starting (``INFO``, in ``color``). Sent with the next flush."""
        if self._stream is None:
            return
        self._buffer.text(paths.ALLOCATION_LOG, float(sim_time), int(repetition), text,
                          _EVENT_COLOR if color is None else color, level)

    def _style(self, entity: str, name: str, color: tuple[int, int, int]) -> None:
        if entity not in self._styled:
            self._styled.add(entity)
            self._stream.log(entity, styles.decision_style(name, color), static=True)

    def flush(self) -> None:
        """Send every buffered tick and decision now (the V_th lines span the flushed ticks)."""
        if self._stream is None or not self._buffer:
            return
        if self._span:
            (t0, r0), (t1, r1) = self._span
            times, reps = np.array([t0, t1]), np.array([r0, r1])
            if self._one_threshold:
                self._buffer.scalars(paths.KWEAR_THRESHOLD, times, reps, np.full(2, self._v_th[0]))
            else:
                for j, joint in enumerate(KWEAR_JOINTS):
                    self._buffer.scalars(join(paths.KWEAR_THRESHOLD, joint), times, reps,
                                         np.full(2, self._v_th[j]))
        self._buffer.send(self._stream)
        self._span = None
        self._pending = 0

    # -- end ------------------------------------------------------------------------------------------------
    def close(self, *, commit: bool = True, timeout: float | None = None) -> None:
        """Flush and close every sink; an .rrd file is complete under its final name when this returns.

        The flush waits at most ``timeout`` seconds (default ``_FLUSH_TIMEOUT``) for the sinks (a viewer
        that is not there, a URL nobody listens on); then the .rrd file is still committed and
        :class:`~ergosim.errors.RecordingError` says which sink did not take the recording.
        """
        failure = None
        try:
            self.flush()
        finally:
            stream, self._stream = self._stream, None
            if stream is not None:
                try:
                    stream.flush(timeout_sec=_FLUSH_TIMEOUT if timeout is None else timeout)
                except RuntimeError as err:  # rerun: "gRPC has been unable to connect for 6s, uri: ..."
                    failure = " ".join(str(err).split())
                stream.disconnect()
            if self._on_close is not None:
                on_close, self._on_close = self._on_close, None
                on_close(commit)
        if failure is not None:
            raise RecordingError(f"the recording did not reach the viewer: {failure}",
                                 where="--spawn/--connect")

    def __enter__(self) -> TwinRecorder:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(commit=exc_type is None)


def _checked(name: str, values: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    _check(name, array, shape)
    return array


def _check(name: str, array: np.ndarray, shape: tuple[int, ...]) -> None:
    if array.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {array.shape}")
