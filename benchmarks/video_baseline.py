"""The video of another git revision beside this checkout's (``scripts/bench_video.py --baseline REV``).

A frame's cost and look come from two things a revision holds: the robots' meshes under ``models/`` and the
render settings (:class:`~ergosim.video.frames.RenderQuality`). :func:`baseline_cell` builds a workcell from
``REV``'s models (the bodies, joints and collision geoms are the same, so a run recorded here poses it);
:func:`baseline_quality` reads ``REV``'s default settings. :func:`compare_revisions` films the same
recorded run with both, interleaved repeat by repeat so both see the same machine load, and :func:`stills`
renders chosen frames of it for a side-by-side look.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import statistics
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from benchmarks.revision import modules_at, tree_at
from benchmarks.video import compare_workers
from ergosim.robot import model as robot_model
from ergosim.scenes.cellspec import View
from ergosim.scenes.workcell import Workcell
from ergosim.twin.records import SubjectRun
from ergosim.video.frames import RenderQuality, gl_used
from ergosim.video.poses import PoseTrack
from ergosim.video.render_pool import FrameSpec
from ergosim.video.run_video import EVENT_HOLD, action_texts
from ergosim.video.timeline import RunTimeline

__all__ = ["baseline_cell", "baseline_quality", "compare_revisions", "stills"]


def baseline_cell(rev: str, build: Callable[[], Workcell]) -> Workcell:
    """``build()`` (e.g. ``lambda: subject_cell(scenario, subject)``) with the robot models of revision
    ``rev``: its ``models/`` folder is written to a temporary folder and read in place of this checkout's
    while the cell compiles (MuJoCo reads the mesh files then, not later)."""
    with tempfile.TemporaryDirectory() as tmp:
        models = tree_at(rev, "models", tmp)
        saved = robot_model.MODELS_DIR
        robot_model.MODELS_DIR = models  # model_dir() reads it at each call
        try:
            return build()
        finally:
            robot_model.MODELS_DIR = saved


def baseline_quality(rev: str) -> RenderQuality:
    """The default :class:`RenderQuality` of revision ``rev`` (the fields both revisions have)."""
    theirs = modules_at(rev, "ergosim.video", ("frames",))["frames"].RenderQuality()
    ours = {f.name for f in dataclasses.fields(RenderQuality)}
    return RenderQuality(**{k: v for k, v in dataclasses.asdict(theirs).items() if k in ours})


def _summary(films: list[dict], seconds: float) -> dict:
    def med(key: str, f) -> float:
        return statistics.median(f(x[key]) for x in films)

    return {"ms_per_frame": 1000 * med("pool", lambda x: x["wall_s"] / x["frames"]),
            "cpu_ms_per_frame": 1000 * med("pool", lambda x: x["cpu_s"] / x["frames"]),
            "render_ms_per_frame": 1000 * med("pool", lambda x: x["render_s"] / x["frames"]),
            "overlay_ms_per_frame": 1000 * med("pool", lambda x: x["overlay_s"] / x["frames"]),
            "one_process_ms_per_frame": 1000 * med("single", lambda x: x["wall_s"] / x["frames"]),
            "one_process_cpu_ms_per_frame": 1000 * med("single", lambda x: x["cpu_s"] / x["frames"]),
            "wall_per_sim_second": med("pool", lambda x: x["wall_s"] / seconds),
            "identical_mp4": all(x["identical"] for x in films)}


def compare_revisions(films: dict[str, tuple[Workcell, RenderQuality]], run: SubjectRun, *, repeats: int,
                      window: tuple[float, float], size: tuple[int, int], speed: float, workers: int) -> dict:
    """Film ``window`` of ``run`` with each (cell, quality) of ``films`` (e.g. ``current`` and ``baseline``),
    ``repeats`` times, in turn within each repeat (the order reversed every other repeat); each film is made
    with ``workers`` processes and in one process (:func:`~benchmarks.video.compare_workers`).
    Returns per name the medians over repeats of ms per frame (wall and CPU), and the load average (1 min)
    before and after each repeat. With ``current`` and ``baseline``, ``speedup``: the median over repeats of
    the baseline's wall time over the current one's (both with ``workers`` processes).

    Call it before this process renders anything (:func:`stills` after it): the one-process films are made
    in forked children, which cannot use an OpenGL context inherited from here.
    """
    if gl_used():
        raise RuntimeError("compare_revisions must run before this process opens an OpenGL context")
    names = list(films)
    made: dict[str, list[dict]] = {k: [] for k in names}
    load = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeats):
            before = os.getloadavg()[0]
            for name in names if k % 2 == 0 else names[::-1]:
                cell, quality = films[name]
                made[name].append(compare_workers(cell, run, Path(tmp), window, size, speed, workers,
                                                  tag=f"{name}{k}", quality=quality))
            load.append((before, os.getloadavg()[0]))
    seconds = window[1] - window[0]
    res: dict = {"repeats": repeats, "size": list(size), "speed": speed, "sim_seconds": seconds,
                 "frames": made[names[0]][0]["pool"]["frames"], "workers": workers,
                 "load_1min": [list(x) for x in load]}
    for name in names:
        cell, quality = films[name]
        res[name] = {"quality": dataclasses.asdict(quality), "mesh_faces": int(cell.model.nmeshface),
                     **_summary(made[name], seconds)}
    if {"current", "baseline"} <= set(names):
        res["speedup"] = statistics.median(b["pool"]["wall_s"] / c["pool"]["wall_s"]
                                           for b, c in zip(made["baseline"], made["current"], strict=True))
        res["cpu_ratio"] = statistics.median(b["pool"]["cpu_s"] / c["pool"]["cpu_s"]
                                             for b, c in zip(made["baseline"], made["current"], strict=True))
    return res


def stills(cell: Workcell, run: SubjectRun, times: Sequence[float], quality: RenderQuality,
           size: tuple[int, int] = (960, 540), view: View | None = None) -> list[np.ndarray]:
    """The video frames of ``run`` at simulated ``times`` [s] with the overlay, as ``--video`` draws them:
    (height, width, 3) uint8 each, from ``view`` (default the cell's first)."""
    pos, quat = run.bodies
    timeline = RunTimeline(run, action_texts(cell),
                           frozenset(a for a, g in cell.actions.items() if g.handover))
    track = PoseTrack(timeline.t, pos, quat)
    spec = FrameSpec(cell.model, view or cell.config.view(None), size[0], size[1], quality)
    overlay = spec.overlay()
    with contextlib.closing(spec.renderer()) as renderer:
        renderer.render(*track.at(times[0]))  # a renderer's first picture differs by a level (render_pool)
        return [overlay.draw(renderer.render(*track.at(t)), timeline.at(t, EVENT_HOLD)) for t in times]
