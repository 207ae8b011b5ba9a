"""Videos of a run (issue 16): frames from recorded poses, overlay, the MP4 read back, results untouched."""

from __future__ import annotations

import copy
import csv
import importlib
import json
import os
import shlex
import signal
import subprocess
import sys
import time
import types
from pathlib import Path

import matplotlib.image
import mujoco
import numpy as np
import pytest
from conftest import KV_SHORT

from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment import film
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell, subject_session
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import build_cell
from ergosim.video import (
    FrameInfo,
    Mp4Writer,
    Overlay,
    PoseRenderer,
    PoseTrack,
    RunTimeline,
    VideoRequest,
    action_texts,
    parse_reps,
    parse_size,
    read_mp4,
    write_run_video,
)
from ergosim.video.timeline import Event
from ergosim.viz.reason import reason_text
from ergosim.viz.styles import JOINT_COLORS
from ergosim.worker.subjects import make_subjects


@pytest.fixture(scope="module")
def recorded():
    """One real kwear-validation repetition (hrc) with the body poses kept, and the cell it ran in."""
    sc = load_scenario("kwear-validation", {"repetitions": "1", "modes": "hrc"})
    res = run_subject(sc, 0, 0, ("hrc",), record_mode="hrc")
    return sc, res.runs["hrc"], subject_cell(sc, scenario_subject(sc, 0, 0))


@pytest.mark.slow
def test_the_filmed_subject_is_the_simulated_one(recorded, monkeypatch, tmp_path):
    """A video shows the body the run simulated. kwear-validation's population is all women
    (female_fraction = 1) at its own pace; a subject drawn with the population defaults is someone else."""
    sc, run, _ = recorded
    filmed = {}

    def capture(cell, run, request, **_kw):
        filmed["cell"] = cell

    monkeypatch.setattr(film, "write_run_video", capture)
    result = types.SimpleNamespace(subject=0, name="S01", runs={"hrc": run})
    film.film_subject(sc, 0, result, VideoRequest(tmp_path / "run.mp4", mode="hrc"))
    simulated = subject_session(sc, 0, 0, "h-only", calibrate=False).cell.model
    model = filmed["cell"].model
    assert np.array_equal(model.body_pos, simulated.body_pos) and np.array_equal(model.geom_size,
                                                                                 simulated.geom_size)
    default = subject_cell(sc, make_subjects(1, 0)[0]).model  # the body the video showed before the fix
    assert not np.array_equal(default.body_pos, simulated.body_pos)


@pytest.mark.slow
def test_pose_renderer_draws_what_mujoco_draws_from_the_live_state():
    """Poses written into the renderer's own MjData give MuJoCo's own picture of the simulated state."""
    cell = build_cell(load_scenario("multi-subject").cell())
    m, d = cell.model, cell.data
    mujoco.mj_step(m, d, 200)
    qpos, shadow = d.qpos.copy(), m.vis.quality.shadowsize
    view = cell.config.view()
    with PoseRenderer(m, view, width=320, height=240) as pr:
        image = pr.render(d.xpos.copy(), d.xquat.copy())
        ref_model = copy.copy(m)
        ref_model.vis.quality.shadowsize = pr.model.vis.quality.shadowsize
        ref_model.vis.quality.offsamples = pr.model.vis.quality.offsamples
        with mujoco.Renderer(ref_model, 240, 320) as r:
            r.update_scene(d, camera=pr.camera)
            r.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
            ref = r.render()
    diff = np.abs(image.astype(int) - ref.astype(int))
    assert image.std() > 10
    assert diff.max() <= 4 and diff.mean() < 0.1
    assert np.array_equal(d.qpos, qpos) and m.vis.quality.shadowsize == shadow  # the simulation untouched


def test_pose_track_interpolates_and_shows_a_reset_part_where_it_was_put():
    t = np.array([0.0, 0.05, 0.10])
    pos = np.zeros((3, 2, 3))
    pos[:, 0, 0] = [0.0, 0.01, 0.02]  # a hand moving 0.2 m/s
    pos[:, 1, 0] = [0.0, 0.0, 0.5]  # a part laid out again between two ticks
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (3, 2, 1))
    half = np.cos(np.pi / 8), 0.0, 0.0, np.sin(np.pi / 8)  # 45 deg about z
    quat[2, 0] = half
    track = PoseTrack(t, pos, quat)
    p, q = track.at(0.075)
    assert p[0, 0] == pytest.approx(0.015)
    assert np.linalg.norm(q, axis=1) == pytest.approx([1.0, 1.0])
    assert 0 < 2 * np.arctan2(q[0, 3], q[0, 0]) < np.pi / 4
    assert track.at(0.09)[0][1, 0] == 0.5 and track.at(0.06)[0][1, 0] == 0.0  # nearer sample, no slide
    assert np.array_equal(track.at(-1.0)[0], pos[0]) and np.array_equal(track.at(9.0)[0], pos[-1])
    with pytest.raises(ValueError, match="increase"):
        PoseTrack(t[::-1], pos, quat)


def test_timeline_draws_the_runs_own_records(recorded):
    _, run, cell = recorded
    tl = RunTimeline(run, action_texts(cell))
    a = run.allocations[2]
    info = tl.at((a.t_start + a.t_end) / 2, hold=1e9, max_events=1)
    assert (info.action, info.agent, info.repetition) == (a.action, a.agent, 1)
    assert info.action_text == f"{cell.actions[a.action].kind} {cell.actions[a.action].part}"
    decision = next(d for d in run.decisions if d.time <= info.time and d.action == a.action)
    assert info.events == (Event(decision.time, "decision", reason_text(decision), decision.agent),)
    t, kw = run.ticks.column("t"), run.ticks.kwear
    k = len(t) // 2
    assert np.allclose(tl.at(float(t[k]), hold=0).kwear, kw[k])
    assert tl.at(float(t[k]), hold=0).v_th == run.v_th
    assert tl.window((1, 1)) == (run.outcomes[0].t_start, min(run.outcomes[0].t_end + 1.0, float(t[-1])))
    with pytest.raises(ConfigError, match="repetition 2 was not run"):
        tl.window((2, 2))


@pytest.mark.slow
def test_two_seconds_of_a_run_to_mp4_and_back(recorded, tmp_path):
    """Issue 16 proof: 2 s of a real run at 30 fps, read back: frame count, size, non-uniform, moving."""
    _, run, cell = recorded
    a = next(x for x in run.allocations if x.agent == "human")
    path = tmp_path / "clip.mp4"
    stats = write_run_video(cell, run, VideoRequest(path, width=320, height=180), header="test",
                            window=(a.t_start, a.t_start + 2.0), workers=0)  # rendered here: the same MP4
    meta, frames = read_mp4(path)
    assert stats.frames == 61 == len(frames) and stats.seconds == pytest.approx(61 / 30)
    assert meta["size"] == (320, 180) and meta["fps"] == 30.0 and meta["codec"] == "h264"
    assert all(f.shape == (180, 320, 3) for f in frames)
    assert min(f.std() for f in frames) > 20 and len(np.unique(frames[0].reshape(-1, 3), axis=0)) > 500
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 0.5  # the worker moved
    assert stats.sim_start == a.t_start and stats.sim_end == pytest.approx(a.t_start + 2.0)
    assert not [p for p in tmp_path.iterdir() if p.name != "clip.mp4"]  # no temporary file left


def test_a_run_from_another_cell_is_refused(recorded, tmp_path):
    _, run, cell = recorded
    bad = copy.copy(run)
    bad.bodies = (run.bodies[0][:, :3], run.bodies[1][:, :3])
    with pytest.raises(ConfigError, match="not the workcell the run ran in"):
        write_run_video(cell, bad, VideoRequest(tmp_path / "clip.mp4"))
    assert not list(tmp_path.iterdir())


def test_an_interrupted_encoding_leaves_no_file(tmp_path):
    path = tmp_path / "clip.mp4"
    with pytest.raises(KeyboardInterrupt), Mp4Writer(path, 64, 64) as w:
        for k in range(3):
            w.write(np.full((64, 64, 3), 40 * k, np.uint8))
        raise KeyboardInterrupt
    assert not list(tmp_path.iterdir())


def _bar_lengths(image: np.ndarray) -> dict[str, int]:
    """Per joint: the longest horizontal run of pixels in the joint's colour (its KWear bar)."""
    out = {}
    for joint in KWEAR_JOINTS:
        mask = np.all(np.abs(image.astype(int) - JOINT_COLORS[joint]) <= 2, axis=2)
        out[joint] = int(mask.sum(axis=1).max())
    return out


def test_overlay_bars_are_proportional_to_kwear_and_events_shown_only_when_given():
    w, h = 960, 540
    frame = np.full((h, w, 3), 128, np.uint8)
    kwear = np.array([0.1, 0.2, 0.4, 0.8, 1.0])
    info = FrameInfo(time=12.5, repetition=2, repetitions=4, action="a2", agent="robot",
                     action_text="insert L", kwear=kwear, v_th=0.8, events=())
    overlay = Overlay(w, h, header="scenario · subject 0 · hrc", speed=4)
    quiet = overlay.draw(frame, info)
    lengths = _bar_lengths(quiet)
    assert lengths["shoulder"] > 5
    for joint, v in zip(KWEAR_JOINTS, kwear, strict=True):
        assert lengths[joint] == pytest.approx(lengths["shoulder"] * v / 0.1, rel=0.1, abs=2)
    assert np.array_equal(quiet[h // 2:], frame[h // 2:])  # nothing over the scene's lower half
    loud = overlay.draw(frame, FrameInfo(**{**info.__dict__, "events": (
        Event(12.0, "decision", "a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.80", "robot"),)}))
    assert not np.array_equal(loud[h - 60:], frame[h - 60:])
    assert np.array_equal(loud[:h // 2], quiet[:h // 2])


def test_reps_and_size_are_parsed_and_checked():
    assert parse_reps("2", 4) == (2, 2) and parse_reps("2:4", 4) == (2, 4)
    assert parse_reps("3:", 4) == (3, 4) and parse_reps(":2", 4) == (1, 2)
    for bad in ("0", "3:2", "5", "a:b", "1:9"):
        with pytest.raises(ConfigError, match="--video-reps"):
            parse_reps(bad, 4)
    assert parse_size("640x360") == (640, 360)
    for bad in ("641x360", "10x10", "big", "640"):
        with pytest.raises(ConfigError, match="--video-size"):
            parse_size(bad)


def _run(out: Path, *extra: str) -> int:
    """The shared run's arguments (tests/conftest.py) with ``extra``."""
    return main(["run", "kwear-validation", "--reps", "1", "--mode", "hrc", "--jobs", "1", "--quiet",
                 *KV_SHORT, "--out", str(out), *extra])


@pytest.mark.slow
def test_outputs_are_byte_identical_with_and_without_video(kv_run, tmp_path, capsys):
    """Issue 16 proof: the video is made from what the run recorded, after it; no output changes. The plain
    run is the shared one (tests/conftest.py: the same arguments)."""
    plain, filmed = kv_run.out, tmp_path / "filmed"
    assert kv_run.code == 0
    assert _run(filmed, "--video", str(tmp_path / "run.mp4"), "--video-speed", "40", "--video-size",
                "320x180", "--video-reps", "1") == 0
    assert "video: " in capsys.readouterr().out
    names = sorted(p.name for p in plain.iterdir())
    assert names == sorted(p.name for p in filmed.iterdir()) and "summary.json" in names
    for name in names:  # but the report, which shows the video
        if name != "report.html":
            assert (plain / name).read_bytes() == (filmed / name).read_bytes(), name
    assert "<video controls" not in (plain / "report.html").read_text()
    assert '<video controls width="960" src="data:video/mp4;base64,' in (filmed / "report.html").read_text()
    meta, frames = read_mp4(tmp_path / "run.mp4")
    summary = json.loads((filmed / "summary.json").read_text())
    # one repetition at x40 and 30 fps: a frame per 4/3 s of simulated time
    rep = summary["modes"]["hrc"]["repetitions"][0]
    assert summary["complete"] and meta["size"] == (320, 180)
    assert abs(len(frames) - rep["duration_s"] * 30 / 40) <= 2, (len(frames), rep["duration_s"])


@pytest.mark.parametrize(("args", "needle"), [
    (["--video-speed", "2"], "--video-speed: choose what the video shows: give --video FILE.mp4"),
    (["--video", "x.avi"], "--video: the video is written as MP4"),
    (["--video", "x.mp4", "--video-reps", "2"], "--video-reps: repetitions 2:2 are not within 1..1"),
    (["--video", "x.mp4", "--video-speed", "0"], "--video-speed: must be a number in (0, 1000]"),
    (["--video", "x.mp4", "--video-subject", "3"], "--video-subject: must be a subject index in 0..0"),
    (["--video", "x.mp4", "--video-view", "nope"], "--video-view: unknown view 'nope'; the workcell"),
    (["--video", "x.mp4", "--video-size", "99x99"], "--video-size: width and height must be even"),
])
def test_video_options_are_checked_before_any_simulation(args, needle, tmp_path, capsys):
    out = tmp_path / "out"
    assert _run(out, *args) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


@pytest.mark.slow
def test_render_writes_a_still_from_a_named_view(tmp_path, capsys):
    out = tmp_path / "cell.png"
    assert main(["render", "gearbox", "--out", str(out), "--view", "top", "--size", "320x240"]) == 0
    assert "view 'top' of workcell 'gearbox'" in capsys.readouterr().out
    image = matplotlib.image.imread(out)
    assert image.shape[:2] == (240, 320) and image[..., :3].std() > 0.05
    assert main(["render", "gearbox", "--out", str(out), "--view", "side"]) == 2
    assert "--view: unknown view 'side'; the workcell 'gearbox' has: overview, top" in capsys.readouterr().err
    assert main(["render", "gearbox", "--out", str(tmp_path / "cell.jpg")]) == 2


@pytest.mark.slow
def test_sigterm_while_filming_keeps_the_results_and_leaves_no_partial_video(tmp_path):
    out, video = tmp_path / "out", tmp_path / "run.mp4"
    env = {**os.environ, "MUJOCO_GL": "egl"}
    cmd = [sys.executable, "-m", "ergosim.cli", "run", "kwear-validation", "--reps", "1", "--mode", "hrc",
           "--jobs", "1", "--quiet", *KV_SHORT, "--out", str(out), "--video", str(video), "--video-speed",
           "0.25"]
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:  # the results are written before the first frame
        manifest = out / "run.json"
        if manifest.is_file() and json.loads(manifest.read_text())["status"] == "complete":
            break
        time.sleep(0.2)
    time.sleep(3.0)  # well inside the video: 38 s at x0.25 is 4560 frames
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "interrupted by SIGTERM" in err and "Traceback" not in err
    assert json.loads((out / "summary.json").read_text())["complete"] is True
    assert not [p for p in tmp_path.iterdir() if p.name not in ("out",)]  # no run.mp4, no .tmp.mp4


@pytest.mark.parametrize("package", ["ergosim.video", "ergosim.experiment.plots", "ergosim.experiment",
                                     "ergosim.twin"])
def test_every_public_name_exists(package):
    module = importlib.import_module(package)
    assert module.__all__
    for name in module.__all__:
        assert getattr(module, name) is not None, name


@pytest.mark.slow
def test_the_readme_video_command_films_a_hand_over(tmp_path):
    """Issue 27: the README's command filmed a repetition the robot never acted in. The same run without
    the video (the results are byte-identical with it): in the filmed repetitions the robot hands a part
    over and the worker finishes the action."""
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    line = next(x for x in readme.splitlines() if x.startswith("ergosim run ") and "--video " in x)
    args = shlex.split(line)[1:]
    reps = args[args.index("--video-reps") + 1]
    first, _, last = reps.partition(":")
    filmed = range(int(first or 1), int(last or first) + 1)
    kept, skip = [], 0
    for a in args:  # the run without its --video options
        if skip:
            skip -= 1
        elif a.startswith("--video"):
            skip = 1
        else:
            kept.append(a)
    assert main([*kept, "--jobs", "1", "--quiet", "--out", str(tmp_path / "o")]) == 0
    cell = load_scenario(kept[1]).cell()
    handed = {a.label for a in cell.actions if a.handover}
    with (tmp_path / "o" / "allocations.csv").open() as f:
        rows = [r for r in csv.DictReader(f) if int(r["repetition"]) in filmed]
    assert any(r["agent"] == "robot" and r["status"] == "done" and r["action"] in handed for r in rows), rows
