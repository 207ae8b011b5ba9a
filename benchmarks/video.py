"""Timing of a video (``scripts/bench_sim.py --video``): worker processes against one process, side by side.

Each film is timed by wall clock and by CPU time (this process, its workers and the encoder), so a figure
taken while other jobs load the machine still says what the work costs: on an idle machine with c cores
the wall time per frame is at least the CPU time per frame / c. The one-process film is made in a forked
child, so this process never opens an OpenGL context and its workers can be forked.
"""

from __future__ import annotations

import filecmp
import multiprocessing
import resource
import time
from pathlib import Path

from ergosim.scenes.workcell import Workcell
from ergosim.twin.records import SubjectRun
from ergosim.video.frames import RenderQuality
from ergosim.video.run_video import VideoRequest, write_run_video

__all__ = ["time_video", "compare_workers"]


def _cpu() -> float:
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def time_video(cell: Workcell, run: SubjectRun, request: VideoRequest, window: tuple[float, float],
               workers: int, quality: RenderQuality = RenderQuality()) -> dict:
    """Film ``window`` of ``run``; returns frames, wall and CPU [s] (CPU of workers and encoder once they
    ended), and the stage times of :class:`~ergosim.video.run_video.VideoStats`."""
    c0, w0 = _cpu(), time.perf_counter()
    st = write_run_video(cell, run, request, window=window, workers=workers, quality=quality)
    return {"frames": st.frames, "wall_s": time.perf_counter() - w0, "cpu_s": _cpu() - c0,
            "render_s": st.render_s, "overlay_s": st.overlay_s, "encode_s": st.encode_s}


def _in_child(conn, *args) -> None:
    conn.send(time_video(*args))
    conn.close()


def compare_workers(cell: Workcell, run: SubjectRun, folder: Path, window: tuple[float, float],
                    size: tuple[int, int], speed: float, workers: int, tag: str = "",
                    quality: RenderQuality = RenderQuality()) -> dict:
    """One film with ``workers`` processes here and one rendered in one process (in a forked child), and
    whether the two MP4 files are byte-identical: ``{"pool": {...}, "single": {...}, "identical": bool}``."""
    paths = {k: Path(folder) / f"{k}{tag}.mp4" for k in ("pool", "single")}
    requests = {k: VideoRequest(p, width=size[0], height=size[1], speed=speed) for k, p in paths.items()}
    ctx = multiprocessing.get_context("fork")
    ours, theirs = ctx.Pipe()
    child = ctx.Process(target=_in_child, args=(theirs, cell, run, requests["single"], window, 0,
                                                      quality))
    child.start()
    single = ours.recv()
    child.join()
    pool = time_video(cell, run, requests["pool"], window, workers, quality)
    return {"pool": pool, "single": single,
            "identical": filecmp.cmp(paths["pool"], paths["single"], shallow=False)}
