"""Frames rendered in worker processes: the same MP4, byte for byte, as frames rendered in one process."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from ergosim.cli import headless_gl

headless_gl()

from ergosim.experiment.runner import run_subject  # noqa: E402
from ergosim.experiment.scenario import load_scenario  # noqa: E402
from ergosim.experiment.subject import scenario_subject, subject_cell  # noqa: E402
from ergosim.video import VideoRequest, write_run_video  # noqa: E402
from ergosim.video import frames as frames_module  # noqa: E402


@pytest.fixture(scope="module")
def recorded():
    sc = load_scenario("kwear-validation", {"repetitions": "1", "modes": "hrc", "eta_max": "2"})
    res = run_subject(sc, 0, 0, ("hrc",), record_mode="hrc")
    return res.runs["hrc"], subject_cell(sc, scenario_subject(sc, 0, 0))


@pytest.mark.slow
def test_worker_processes_write_the_same_mp4_as_one_process(recorded, tmp_path, monkeypatch):
    run, cell = recorded
    a = next(x for x in run.allocations if x.agent == "human")
    window = (a.t_start, a.t_start + 1.0)
    one = write_run_video(cell, run, VideoRequest(tmp_path / "one.mp4", width=320, height=180),
                          window=window, workers=0)
    monkeypatch.setattr(frames_module, "gl_used", lambda: True)  # fresh interpreters, as after a still
    for n in (1, 2, 3):
        path = tmp_path / f"pool{n}.mp4"
        stats = write_run_video(cell, run, VideoRequest(path, width=320, height=180), window=window,
                                workers=n)
        assert stats.frames == one.frames == 31
        assert path.read_bytes() == (tmp_path / "one.mp4").read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["one.mp4", "pool1.mp4", "pool2.mp4", "pool3.mp4"]


@pytest.mark.slow
def test_forked_workers_write_the_same_mp4_as_one_process(tmp_path):
    """In a fresh interpreter that never opened OpenGL the workers are forked; the one-process film is made
    in a forked child (benchmarks.video), as scripts/bench_sim.py --video does."""
    code = textwrap.dedent(f"""
        from pathlib import Path
        from ergosim.cli import headless_gl
        headless_gl()
        from ergosim.experiment.runner import run_subject
        from ergosim.experiment.subject import scenario_subject, subject_cell
        from ergosim.experiment.scenario import load_scenario
        from ergosim.video import frames
        from benchmarks.video import compare_workers
        sc = load_scenario("kwear-validation", {{"repetitions": "1", "modes": "hrc", "eta_max": "2"}})
        run = run_subject(sc, 0, 0, ("hrc",), record_mode="hrc").runs["hrc"]
        cell = subject_cell(sc, scenario_subject(sc, 0, 0))
        a = next(x for x in run.allocations if x.agent == "human")
        res = compare_workers(cell, run, Path({str(tmp_path)!r}), (a.t_start, a.t_start + 1.0), (320, 180),
                              1.0, 2)
        assert not frames.gl_used()
        print(res["identical"], res["pool"]["frames"], res["single"]["frames"])
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                          check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["True", "31", "31"]
