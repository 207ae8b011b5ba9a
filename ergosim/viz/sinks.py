"""Where a recording goes: an .rrd file (headless), a spawned viewer, a running viewer, or several at once.

rerun's script helpers (``rr.script_setup``) pick exactly one sink and use the global recording; the twin
may save and watch at the same time and runs subjects in parallel processes, so it builds its own
``RecordingStream`` and tees it with ``set_sinks``. The .rrd file is written under a temporary name beside
the target and renamed when the recorder closes, like every other output (:mod:`ergosim.atomic`): a
crashed run never leaves a half file under the final name.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import rerun as rr

from ergosim.atomic import check_output_file
from ergosim.errors import ConfigError
from ergosim.viz.blueprint import build_blueprint
from ergosim.viz.recorder import TwinRecorder

__all__ = ["DEFAULT_URL", "SPAWN_PORT", "SPAWN_HOST", "SinkPlan", "plan_sinks", "open_recording",
           "spawn_viewer"]

SPAWN_PORT = 9876
SPAWN_HOST = "127.0.0.1"
"""The spawned viewer listens on the loopback interface only: its gRPC proxy has no authentication."""
_SPAWN_WAIT = 15.0  # s for a spawned viewer to listen (assumed: it starts in about a second)
DEFAULT_URL = f"rerun+http://127.0.0.1:{SPAWN_PORT}/proxy"
"""Where a viewer started with ``rerun`` (or ``--spawn``) listens."""

_SCHEMES = ("rerun://", "rerun+http://", "rerun+https://")


@dataclasses.dataclass(frozen=True)
class SinkPlan:
    """The sinks requested, checked but not opened: an .rrd path, whether to spawn a viewer, gRPC URLs."""

    rrd: Path | None
    spawn: bool
    urls: tuple[str, ...]

    @property
    def empty(self) -> bool:
        return self.rrd is None and not self.spawn and not self.urls


def plan_sinks(rrd: str | os.PathLike[str] | None = None, spawn: bool = False,
               connect: str | None = None) -> SinkPlan:
    """Check the CLI's ``--rrd FILE``, ``--spawn`` and ``--connect [URL]`` (``"default"`` = DEFAULT_URL).

    Opens nothing. Raises ConfigError for an .rrd path that is a directory or a URL rerun cannot use.
    """
    path = None
    if rrd is not None:
        path = check_output_file(rrd, where="--rrd")
    urls = [DEFAULT_URL] if spawn else []
    if connect is not None:
        url = DEFAULT_URL if connect == "default" else connect
        if not url.startswith(_SCHEMES) or not url.rstrip("/").endswith("/proxy"):
            raise ConfigError(f"cannot stream to {url!r}; expected a rerun gRPC URL such as {DEFAULT_URL}",
                              where="--connect")
        if url not in urls:
            urls.append(url)
    return SinkPlan(path, bool(spawn), tuple(urls))


def open_recording(rrd: str | os.PathLike[str] | None = None, spawn: bool = False, connect: str | None = None,
                   application_id: str = "ergosim", *, recording_id: str | None = None,
                   recording_name: str | None = None) -> TwinRecorder:
    """A :class:`TwinRecorder` logging to the requested sinks, or a no-op recorder if none is requested.

    ``rrd``: file to save (complete after ``close()``); ``spawn``: start a viewer on SPAWN_PORT and stream
    to it; ``connect``: stream to a running viewer, ``"default"`` for DEFAULT_URL. Every sink receives
    the blueprint of :func:`ergosim.viz.build_blueprint`.
    """
    plan = plan_sinks(rrd, spawn, connect)
    if plan.empty:
        return TwinRecorder(None)
    stream = rr.RecordingStream(application_id, recording_id=recording_id)
    sinks: list[rr.FileSink | rr.GrpcSink] = []
    pending = None
    if plan.rrd is not None:
        pending = _PendingFile(plan.rrd)
        sinks.append(rr.FileSink(pending.tmp))
    try:
        if plan.spawn:
            spawn_viewer(SPAWN_PORT)
        sinks.extend(rr.GrpcSink(url) for url in plan.urls)
        stream.set_sinks(*sinks, default_blueprint=build_blueprint())
        if recording_name:
            stream.send_recording_name(recording_name)
    except BaseException:
        if pending is not None:
            pending.finish(False)
        raise
    return TwinRecorder(stream, on_close=None if pending is None else pending.finish)


def _listening(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.settimeout(0.5)
        return s.connect_ex((SPAWN_HOST, port)) == 0


def spawn_viewer(port: int = SPAWN_PORT, *, wait: float = _SPAWN_WAIT) -> subprocess.Popen | None:
    """Start a rerun viewer bound to 127.0.0.1:``port`` (``rerun --bind 127.0.0.1``) and wait until it
    listens; None if a viewer already listens there. ConfigError, at once and before any simulation, if
    there is no display or the viewer exits or does not listen within ``wait`` seconds."""
    if _listening(port):
        return None
    display = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    if sys.platform.startswith("linux") and not display:
        raise ConfigError("cannot open a viewer: no display (DISPLAY and WAYLAND_DISPLAY are unset); save a "
                          "recording with --rrd FILE instead and open it with `rerun FILE`", where="--spawn")
    exe = Path(sys.executable).with_name("rerun")
    exe = str(exe) if exe.is_file() else shutil.which("rerun")
    if exe is None:
        raise ConfigError("cannot open a viewer: the `rerun` command (from rerun-sdk) is not on PATH",
                          where="--spawn")
    env = {**os.environ, "RERUN_APP_ONLY": "true"}
    log = tempfile.TemporaryFile()  # the viewer's own log, read back only if it fails to start
    proc = subprocess.Popen([exe, "--port", str(port), "--bind", SPAWN_HOST, "--memory-limit", "75%"],
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=log,
                            env=env, start_new_session=True)
    deadline = time.monotonic() + wait
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            log.seek(0)
            last = log.read().decode(errors="replace").strip().splitlines()[-1:]
            raise ConfigError(f"the rerun viewer exited with status {proc.returncode}"
                              + (f": {last[0][:200]}" if last else ""), where="--spawn")
        if _listening(port):
            time.sleep(0.5)  # a viewer without a usable display listens, then exits: see it exit
            if proc.poll() is None:
                return proc
            continue
        time.sleep(0.1)
    proc.kill()
    raise ConfigError(f"the rerun viewer did not listen on {SPAWN_HOST}:{port} within {wait:g} s",
                      where="--spawn")


class _PendingFile:
    """A temporary sibling of ``target`` that becomes ``target`` on commit."""

    def __init__(self, target: Path) -> None:
        self.target = check_output_file(target, where="--rrd")
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        os.close(fd)
        self.tmp = Path(tmp)

    def finish(self, commit: bool) -> None:
        if not commit:
            with contextlib.suppress(FileNotFoundError):
                self.tmp.unlink()
            return
        with open(self.tmp, "rb") as f:
            os.fsync(f.fileno())
        os.chmod(self.tmp, 0o666 & ~_umask())
        os.replace(self.tmp, self.target)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
