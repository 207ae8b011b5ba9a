"""Shared test set-up: offscreen rendering on a machine without a display (read when mujoco is imported),
and the short runs that several test files read.

A shared run is made once per test session, by whichever pytest-xdist worker asks first (the others wait on
a lock, then read the same folder), and its outputs are read-only to the tests: a test that edits a file
copies the folder first. Each run is the smallest that still holds what its readers check; the readers say
what they check in their own docstrings.
"""

from __future__ import annotations

import fcntl
import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import pytest
from hypothesis import settings

from ergosim.cli import headless_gl, main

headless_gl()

# CI draws the same hypothesis examples on every run (derandomize: the examples follow from each test's
# name), so a CI run is repeatable and its time too; a developer's run explores new ones
settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


RUN_FIXTURES = frozenset({
    "kv_run", "kv_two_subjects", "forced_run",  # below, shared by several files
    "local",  # test_sweep_run.py
    "run_dir",  # test_plots.py
    "shards",  # test_run_merge.py
    "parallel_ms", "parallel_gearbox", "negotiating",  # test_team_session.py
    "hrc_run",  # test_twin_loop.py
    "recorded",  # test_video.py
    "reba_run",  # test_reba_run.py
    "bracket",  # test_action_kinds.py
    "ms_h_only", "gearbox_h_only", "pcb_run",  # test_worker_realism.py
    "gearbox_run",  # test_report.py
})
"""Fixtures that run a scenario (seconds each): a test that reads one is ``slow``, so the quick tier
(``-m "not slow"``) never waits for a run."""


def pytest_collection_modifyitems(items) -> None:
    """Tests that read a scenario run (:data:`RUN_FIXTURES`) are marked ``slow``. Files that hold slow tests
    come first, each file's tests in their order: pytest-xdist then starts the long files early and the many
    short ones fill the workers' last minutes (``--no-loadscope-reorder`` in pyproject.toml keeps this
    order; xdist's own puts the files with the most tests first)."""
    for item in items:
        if RUN_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)
    slow = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow)


class SharedRun(NamedTuple):
    """A finished ``ergosim run``: its output folder, its rerun recording (None if not recorded) and its
    exit status, which each reader asserts as it did when it made the run itself."""

    out: Path
    rrd: Path | None
    code: int


KV_SHORT = ("--set", "eta_max=2")
"""The §7.1 cell's calibration shortened to two executions per action (its default of ten makes a
one-repetition run mostly calibration): for the shared runs whose readers check the loop, the files and the
pictures, not α."""


def _session_dir(tmp_path_factory) -> Path:
    """A folder every worker of this pytest session sees (xdist gives each worker a base temp dir inside
    the session's own)."""
    base = tmp_path_factory.getbasetemp()
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "shared-runs"
    root.mkdir(exist_ok=True)
    return root


def shared_run(tmp_path_factory, name: str, args: Sequence[str], *, rrd: bool = False) -> SharedRun:
    """``ergosim run ARGS --out DIR [--rrd FILE]`` in-process, once per session."""
    root = _session_dir(tmp_path_factory)
    out, recording, done = root / name / "out", root / name / "run.rrd", root / name / "exit.json"
    with (root / f"{name}.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
        if not done.exists():
            out.parent.mkdir(exist_ok=True)
            argv = ["run", *args, "--out", str(out), *(["--rrd", str(recording)] if rrd else [])]
            done.write_text(json.dumps({"argv": argv, "code": main(argv)}))
    return SharedRun(out, recording if rrd else None, json.loads(done.read_text())["code"])


@pytest.fixture(scope="session")
def kv_run(tmp_path_factory) -> SharedRun:
    """The §7.1 cell, 1 subject, 1 repetition, hrc, seed 0, recorded (the recording changes no output);
    calibrated on two executions per action (:data:`KV_SHORT`)."""
    return shared_run(tmp_path_factory, "kv", ["kwear-validation", "--reps", "1", "--mode", "hrc",
                                               "--jobs", "1", "--quiet", *KV_SHORT], rrd=True)


@pytest.fixture(scope="session")
def kv_two_subjects(tmp_path_factory) -> SharedRun:
    """The §7.1 cell, 2 subjects, 1 repetition, hrc and rula, one process; subject 1's rula run recorded and
    subject 1 alone in the timelines."""
    return shared_run(tmp_path_factory, "kv2", ["kwear-validation", "--subjects", "2", "--reps", "1",
                                                "--jobs", "1", "--quiet", "--rrd-subject", "1",
                                                "--rrd-mode", "rula", "--plot-subject", "1", *KV_SHORT],
                      rrd=True)


@pytest.fixture(scope="session")
def forced_run(tmp_path_factory) -> SharedRun:
    """The issue-14 example, shortened: the multi-subject cell with L (l_xy=0.14,0.88) out of the reach of a
    worker whose feet stay planted, 1 subject, 2 repetitions, hrc, recorded. The robot's hyper-arcs cost 50
    (the §7.1 figure) so that the planner offers every action to the worker first: each repetition's a2 is a
    worker failure then a forced robot action, whatever the robot's timing."""
    args = ["multi-subject", "--subjects", "1", "--reps", "2", "--mode", "hrc", "--jobs", "1", "--quiet",
            "--set", "scene.l_xy=0.14,0.88", "--set", "scene.worker.standing_area=0,0,0,0",
            "--set", "scene.worker.max_turn=0", "--set", "robot_cost=50"]
    return shared_run(tmp_path_factory, "forced", args, rrd=True)
