"""Speed of a BVH replay (``scripts/bench_bvh.py``): ``ergosim replay`` end to end, and its stages.

A synthetic recording (:func:`synthetic_angles`: minimum-jerk moves between random postures inside the
joints' ranges of motion, seeded) is written once with the project's exporter, then replayed ``repeats``
times: the whole command in-process (``ergosim replay FILE --out DIR``: parse, mapping, RULA, KWear,
ticks.csv, summary.json and the KWear timeline PNG), and each stage on its own in the same loop. Figures
are medians of the repeats [s], wall and CPU time.
"""

from __future__ import annotations

import contextlib
import io
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ergosim.human.joints import joint_spec
from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.bvh import save_bvh
from ergosim.worker.minimum_jerk import interpolate_keyframes

__all__ = ["STAGES", "synthetic_angles", "write_synthetic_bvh", "time_stages", "bench_bvh"]

STAGES = ("parse", "mapping", "rula_kwear", "csv", "summary")
"""Stages timed on their own: read and parse the file, map the skeleton onto the canonical angles, RULA and
KWear over the ergonomics ticks, write ticks.csv, write summary.json."""

_REACH = 0.6  # keyframes span this share of each joint's range of motion (assumed: everyday work postures)


def synthetic_angles(duration_s: float, rate_hz: float, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Canonical angles [deg], name -> (n,), of ``duration_s`` [s] at ``rate_hz`` [Hz]: minimum-jerk moves
    between random postures held 0.5-2.5 s apart, every joint inside the middle of its range of motion."""
    n = int(round(duration_s * rate_hz))
    gaps = rng.uniform(0.5, 2.5, int(duration_s / 0.5) + 2)
    key_t = np.concatenate([[0.0], np.cumsum(gaps)])
    ranges = np.array([joint_spec(name).range_deg for name in HUMAN_JOINTS])
    mid, half = ranges.mean(axis=1), 0.5 * _REACH * (ranges[:, 1] - ranges[:, 0])
    keys = mid + half * rng.uniform(-1.0, 1.0, (len(key_t), len(HUMAN_JOINTS)))
    keys[0] = 0.0
    q = interpolate_keyframes(key_t, keys, np.arange(n) / rate_hz)
    return {name: q[:, k] for k, name in enumerate(HUMAN_JOINTS)}


def write_synthetic_bvh(path: str | Path, duration_s: float = 3600.0, rate_hz: float = 60.0,
                        seed: int = 0) -> Path:
    """Write :func:`synthetic_angles` as a BVH file with the project's skeleton; returns the path."""
    save_bvh(path, synthetic_angles(duration_s, rate_hz, np.random.default_rng(seed)), rate_hz)
    return Path(path)


def _timed(fn: Callable[[], object]) -> tuple[float, float, object]:
    """(wall [s], CPU time of this process [s], result) of ``fn()``."""
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return time.perf_counter() - w, time.process_time() - c, out


def time_stages(path: Path, out: Path, rate: float = 20.0) -> dict[str, tuple[float, float]]:
    """(wall, CPU) [s] of each of :data:`STAGES` once, the way ``ergosim replay`` runs them (right arm)."""
    from ergosim.atomic import write_json  # noqa: PLC0415
    from ergosim.commands.replay import replay_summary, side_angles, write_ticks  # noqa: PLC0415
    from ergosim.ergonomics.kwear import KWearParams  # noqa: PLC0415
    from ergosim.worker import replay_ticks, tick_indices  # noqa: PLC0415
    from ergosim.worker.bvh import recording_from_data  # noqa: PLC0415
    from ergosim.worker.bvh_parse import parse_bvh  # noqa: PLC0415

    params = KWearParams()
    s: dict[str, tuple[float, float]] = {}
    *s["parse"], data = _timed(lambda: parse_bvh(path))
    *s["mapping"], recording = _timed(lambda: recording_from_data(
        data, frames=tick_indices(data.n_frames, data.rate_hz, rate)))
    *s["rula_kwear"], trace = _timed(lambda: replay_ticks(side_angles(recording, "right"), recording.frames,
                                                          params, rate=rate))
    out.mkdir(parents=True, exist_ok=True)
    *s["csv"], _ = _timed(lambda: write_ticks(out / "ticks.csv", trace))
    *s["summary"], _ = _timed(lambda: write_json(out / "summary.json",
                                                 replay_summary(trace, recording, params, None)))
    return s


def bench_bvh(workdir: str | Path, duration_s: float = 3600.0, rate_hz: float = 60.0, repeats: int = 3,
              seed: int = 0, progress: Callable[[str], None] | None = None) -> dict:
    """Median wall and CPU times [s] of ``ergosim replay`` end to end and of its stages on a synthetic
    recording. The CPU time of this process is what the wall time would be on an idle machine (the work is
    single-threaded); on a shared one the wall time also holds the other jobs' share.

    Returns ``{"recording": {...}, "repeats", "end_to_end_s", "end_to_end_cpu_s", "stages_s": {stage: s},
    "stages_cpu_s": {stage: s}, "runs": [...]}``; ``runs`` holds every repeat's figures.
    """
    from ergosim.cli import main  # noqa: PLC0415

    workdir = Path(workdir)
    path = write_synthetic_bvh(workdir / "bench.bvh", duration_s, rate_hz, seed)
    runs = []
    for k in range(repeats):
        with contextlib.redirect_stdout(io.StringIO()):
            wall, cpu, code = _timed(lambda: main(["replay", str(path), "--out", str(workdir / "replay")]))
        if code != 0:
            raise RuntimeError(f"ergosim replay exited with {code}")
        stages = time_stages(path, workdir / "stages")
        runs.append({"end_to_end_s": wall, "end_to_end_cpu_s": cpu,
                     "stages_s": {st: w for st, (w, _) in stages.items()},
                     "stages_cpu_s": {st: c for st, (_, c) in stages.items()}})
        if progress is not None:
            progress(f"repeat {k + 1}/{repeats}: end to end {wall:.2f} s (CPU {cpu:.2f} s); "
                     + ", ".join(f"{st} {w:.2f}/{c:.2f}" for st, (w, c) in stages.items()))
    med = statistics.median
    return {
        "recording": {"duration_s": duration_s, "rate_hz": rate_hz, "seed": seed,
                      "frames": int(round(duration_s * rate_hz)), "bytes": path.stat().st_size},
        "repeats": repeats,
        "end_to_end_s": med(r["end_to_end_s"] for r in runs),
        "end_to_end_cpu_s": med(r["end_to_end_cpu_s"] for r in runs),
        "stages_s": {st: med(r["stages_s"][st] for r in runs) for st in STAGES},
        "stages_cpu_s": {st: med(r["stages_cpu_s"][st] for r in runs) for st in STAGES},
        "runs": runs,
    }
