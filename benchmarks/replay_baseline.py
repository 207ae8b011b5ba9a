"""``ergosim replay`` of this checkout and of another git revision, side by side (bench_bvh.py --baseline).

Each side is a long-lived Python process that imports its own ``ergosim`` (this checkout, or the revision's
``ergosim/`` unpacked with ``git archive``) and replays the same recording whenever asked; the two are
asked in turn, so both see the same machine load, and each repeat is timed inside its process after a
warm-up replay (imports and first-call costs excluded, as in :func:`~benchmarks.replay.
bench_bvh`). The outputs of the last repeats are compared byte for byte.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
from collections.abc import Callable
from pathlib import Path

__all__ = ["OUTPUTS", "unpack_revision", "side_by_side"]

OUTPUTS = ("ticks.csv", "summary.json", "kwear_timeline_right.png")
"""Files of a single-side replay compared between the two revisions."""

ROOT = Path(__file__).resolve().parents[1]

# Uses only ergosim.cli.main, which every revision has: one JSON line in (argv), one JSON line out.
_SERVER = """
import contextlib, io, json, sys, time
from ergosim.cli import main
for line in sys.stdin:
    argv = json.loads(line)
    w, c = time.perf_counter(), time.process_time()
    with contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    print(json.dumps({"wall": time.perf_counter() - w, "cpu": time.process_time() - c, "code": code}),
          flush=True)
"""


def unpack_revision(rev: str, dest: str | Path) -> Path:
    """``ergosim/`` of git revision ``rev`` of this checkout, unpacked under ``dest``; returns ``dest``."""
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryFile() as tar:
        subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", rev, "ergosim"], stdout=tar,
                       check=True)
        tar.seek(0)
        with tarfile.open(fileobj=tar) as tf:
            tf.extractall(dest, filter="data")
    return dest


class _Side:
    """One revision's replay process."""

    def __init__(self, pythonpath: Path) -> None:
        env = {**os.environ, "PYTHONPATH": str(pythonpath), "MPLBACKEND": "Agg"}
        self.proc = subprocess.Popen([sys.executable, "-c", _SERVER], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True, env=env, cwd=pythonpath)

    def replay(self, argv: list[str]) -> dict:
        self.proc.stdin.write(json.dumps(argv) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the replay process of {self.proc.args} ended (exit {self.proc.wait()})")
        res = json.loads(line)
        if res["code"] != 0:
            raise RuntimeError(f"ergosim replay exited with {res['code']}")
        return res

    def close(self) -> None:
        self.proc.stdin.close()
        self.proc.wait()


def side_by_side(path: Path, workdir: Path, rev: str, repeats: int,
                 progress: Callable[[str], None] | None = None) -> dict:
    """Median wall and CPU [s] of ``ergosim replay path`` with this checkout's code and with ``rev``'s,
    interleaved repeat by repeat, and whether each of :data:`OUTPUTS` is byte-identical.

    Returns ``{"baseline_rev", "current": {"end_to_end_s", "end_to_end_cpu_s", "runs"}, "baseline": {...},
    "speedup_cpu", "speedup_wall", "identical": {file: bool}}``.
    """
    src = unpack_revision(rev, workdir / "baseline_src")
    sides = {"current": _Side(ROOT), "baseline": _Side(src)}
    runs: dict[str, list[dict]] = {k: [] for k in sides}
    try:
        for name, side in sides.items():  # warm-up: imports, first calls
            side.replay(["replay", str(path), "--out", str(workdir / f"out_{name}")])
        for k in range(repeats):
            order = list(sides) if k % 2 == 0 else list(sides)[::-1]
            for name in order:
                argv = ["replay", str(path), "--out", str(workdir / f"out_{name}")]
                runs[name].append(sides[name].replay(argv))
            if progress is not None:
                progress(f"side by side {k + 1}/{repeats}: " + ", ".join(
                    f"{n} {runs[n][-1]['wall']:.2f} s wall / {runs[n][-1]['cpu']:.2f} s CPU" for n in sides))
    finally:
        for side in sides.values():
            side.close()
    med = statistics.median
    res: dict = {"baseline_rev": rev}
    for name, r in runs.items():
        res[name] = {"end_to_end_s": med(x["wall"] for x in r), "end_to_end_cpu_s": med(x["cpu"] for x in r),
                     "runs": r}
    res["speedup_cpu"] = res["baseline"]["end_to_end_cpu_s"] / res["current"]["end_to_end_cpu_s"]
    res["speedup_wall"] = res["baseline"]["end_to_end_s"] / res["current"]["end_to_end_s"]
    cur, base = workdir / "out_current", workdir / "out_baseline"
    res["identical"] = {f: (cur / f).read_bytes() == (base / f).read_bytes() for f in OUTPUTS}
    return res
