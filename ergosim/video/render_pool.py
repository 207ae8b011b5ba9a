"""Video frames rendered and overlaid in worker processes and handed back in frame order.

A frame costs mostly MuJoCo's scene render on the CPU (Mesa llvmpipe), whose rasteriser threads share the
work of one frame poorly; whole frames in separate processes use the cores fully. Frame k goes to worker
k mod n and each worker renders its frames in order, so reading the results round-robin gives them in
order: the encoder receives the same frames as from one process, and the MP4 is the same file.

Workers are forked while this process has no OpenGL context of its own (no GL state to inherit, and no
imports to repeat); otherwise each is a fresh interpreter that imports only what it needs (never the
caller's ``__main__``). Each runs llvmpipe with one rasteriser thread (``LP_NUM_THREADS=1``): the
processes are the parallelism.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import subprocess
import sys
import time
from collections import deque
from collections.abc import Iterable, Iterator
from multiprocessing.connection import Connection

import mujoco
import numpy as np

from ergosim.errors import RenderError
from ergosim.scenes.cellspec import View
from ergosim.video import frames as frames_module
from ergosim.video.frames import PoseRenderer, RenderQuality
from ergosim.video.overlay import Overlay
from ergosim.video.timeline import FrameInfo

__all__ = ["FrameSpec", "RenderPool", "default_workers", "spawned_main"]

_IN_FLIGHT = 2  # frames queued per worker: one rendering, one waiting, so a worker never idles


def default_workers() -> int:
    """Worker processes for a video: 2 on a machine with 2 or more cores (the encoder and this process take
    little), else 0 (render here)."""
    return 2 if (os.cpu_count() or 1) >= 2 else 0


@dataclasses.dataclass(frozen=True)
class FrameSpec:
    """What every worker builds once: the renderer (model, camera view, size, quality) and the overlay
    (header, speed, text scale)."""

    model: mujoco.MjModel
    view: View
    width: int
    height: int
    quality: RenderQuality
    header: str = ""
    speed: float = 1.0
    text_scale: float = 1.0

    def renderer(self) -> PoseRenderer:
        return PoseRenderer(self.model, self.view, width=self.width, height=self.height, quality=self.quality)

    def overlay(self) -> Overlay:
        return Overlay(self.width, self.height, header=self.header, speed=self.speed,
                       text_scale=self.text_scale)


def _serve(inbox: Connection, outbox: Connection, spec: FrameSpec) -> None:
    """Worker loop: build, say ready (or the error), then render (pos, quat, info, warm) jobs until None.

    ``warm``: render the frame once before the one kept. A renderer's first picture differs from its later
    ones in a few pixels by a level or two (llvmpipe's first frame), so the worker that renders the
    video's first frame keeps its first picture, as one process would, and every other worker renders
    its first frame twice.
    """
    os.environ["LP_NUM_THREADS"] = "1"
    try:
        renderer, overlay = spec.renderer(), spec.overlay()
    except Exception as err:  # noqa: BLE001 - any failure to build is reported as one line
        outbox.send(("error", " ".join(str(err).split())))
        return
    outbox.send(("ready", ""))
    try:
        while (job := inbox.recv()) is not None:
            pos, quat, info, warm = job
            c0 = time.perf_counter()
            if warm:
                renderer.render(pos, quat)
            image = renderer.render(pos, quat)
            c1 = time.perf_counter()
            image = overlay.draw(image, info)
            outbox.send((time.perf_counter() - c1, c1 - c0))
            outbox.send_bytes(memoryview(np.ascontiguousarray(image, dtype=np.uint8)).cast("B"))
    except (EOFError, OSError, KeyboardInterrupt):
        pass  # the caller closed the pipes (it finished, failed or was stopped): nothing left to do
    finally:
        renderer.close()


def _forked(conn: Connection, spec: FrameSpec) -> None:
    _serve(conn, conn, spec)


def spawned_main(read_fd: int, write_fd: int) -> None:
    """Entry of a worker started as a fresh interpreter: the spec, then jobs, on the inherited pipes."""
    inbox, outbox = Connection(read_fd, writable=False), Connection(write_fd, readable=False)
    try:
        spec = inbox.recv()
    except (EOFError, OSError, KeyboardInterrupt):
        return  # the caller stopped before sending the spec
    _serve(inbox, outbox, spec)


class _Spawned:
    """A worker in a fresh interpreter, talking over two pipes (a :class:`Connection` each way)."""

    def __init__(self, spec: FrameSpec) -> None:
        to_child, from_parent = os.pipe()
        to_parent, from_child = os.pipe()
        code = f"from ergosim.video.render_pool import spawned_main; spawned_main({to_child}, {from_child})"
        self.proc = subprocess.Popen([sys.executable, "-c", code], pass_fds=(to_child, from_child))
        os.close(to_child)
        os.close(from_child)
        self.send_conn = Connection(from_parent, readable=False)
        self.recv_conn = Connection(to_parent, writable=False)
        self.send_conn.send(spec)

    def join(self, timeout: float) -> bool:
        try:
            self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.terminate()
            self.proc.wait()
        return True


class _Forked:
    def __init__(self, spec: FrameSpec) -> None:
        ours, theirs = multiprocessing.get_context("fork").Pipe()
        self.proc = multiprocessing.get_context("fork").Process(target=_forked, args=(theirs, spec),
                                                                daemon=True)
        self.proc.start()
        theirs.close()
        self.send_conn = self.recv_conn = ours

    def join(self, timeout: float) -> bool:
        self.proc.join(timeout)
        if self.proc.is_alive():
            self.proc.terminate()
            self.proc.join()
        return True


class RenderPool:
    """``with RenderPool(spec, workers=2) as pool: for image, render_s, overlay_s in pool.frames(jobs)``,
    jobs being (pos (nbody, 3), quat (nbody, 4) wxyz, :class:`FrameInfo`) in frame order."""

    def __init__(self, spec: FrameSpec, workers: int = 2) -> None:
        if workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers}")
        start = _Spawned if frames_module.gl_used() else _Forked
        self.spec = spec
        self._workers: list[_Spawned | _Forked] = []
        try:
            for _ in range(workers):
                self._workers.append(start(spec))
            for worker in self._workers:
                kind, what = self._recv(worker.recv_conn)
                if kind == "error":
                    raise RenderError(what, where="render")
        except BaseException:
            self.close()
            raise

    @staticmethod
    def _recv(conn: Connection):
        try:
            return conn.recv()
        except (EOFError, OSError):
            raise RenderError("a video worker process ended unexpectedly", where="render") from None

    def frames(self, jobs: Iterable[tuple[np.ndarray, np.ndarray, FrameInfo]]
               ) -> Iterator[tuple[np.ndarray, float, float]]:
        """(height, width, 3) uint8 images in the order of ``jobs``, with the worker's render and overlay
        wall times [s] for each."""
        n = len(self._workers)
        shape = (self.spec.height, self.spec.width, 3)
        pending: deque[int] = deque()
        sent = 0

        def receive() -> tuple[np.ndarray, float, float]:
            conn = self._workers[pending.popleft() % n].recv_conn
            overlay_s, render_s = self._recv(conn)
            image = np.frombuffer(conn.recv_bytes(), dtype=np.uint8).reshape(shape)
            return image, render_s, overlay_s

        for job in jobs:
            self._workers[sent % n].send_conn.send((*job, 0 < sent < n))
            pending.append(sent)
            sent += 1
            if len(pending) >= n * _IN_FLIGHT:
                yield receive()
        while pending:
            yield receive()

    def close(self) -> None:
        for worker in self._workers:
            try:
                worker.send_conn.send(None)
            except (OSError, ValueError):
                pass
        for worker in self._workers:
            worker.join(timeout=5.0)
            for conn in {worker.send_conn, worker.recv_conn}:
                conn.close()
        self._workers = []

    def __enter__(self) -> RenderPool:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
