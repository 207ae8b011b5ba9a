"""Replay of recordings through the ergonomics tick (paper eq. 3-5), in the twin and from ``ergosim replay``.

KWear is checked against an independent recursion (RULA of the sampled frames, then ``kwear_step`` tick by
tick) and the closed forms of eq. 4 and 5; dropouts against the rule of the risk index: counted, V holds
while acting, never NaN -- from synthetic frames, and from a real twin segment measured with dropouts.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.ergonomics.kwear import KWearParams, kwear_step
from ergosim.ergonomics.param_store import ParamStore, WorkerParams
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.ergonomics.rula import RULA_PARTS, part_scores, rula
from ergosim.errors import ConfigError, RecordingError
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS, STANCE, array_to_posture
from ergosim.scenes import build_scene
from ergosim.twin.loop import Plant
from ergosim.twin.records import TICK_COLUMNS
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker import (
    REPLAY_COLUMNS,
    MocapStream,
    Subject,
    Worker,
    load_bvh,
    replay,
    score_frames,
    tick_indices,
)
from ergosim.worker.motion import WORKER_MEASURES

DATA = Path(__file__).parent / "data"
BVH = DATA / "reach_overhead.bvh"
P = KWearParams()
M = len(KWEAR_JOINTS)


def _frames(n: int, seed: int = 0) -> np.ndarray:
    """(n, 14) smooth, varied postures [deg] at 60 Hz: slow sinusoids around a working posture."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)[:, None] / 60.0
    centre = np.array([20, 5, 10, 15, 0, 10, 60, 20, 10, 5, 70, 10, 10, 5], dtype=float)
    amp = rng.uniform(5.0, 40.0, len(ANGLE_NAMES))
    freq = rng.uniform(0.1, 0.6, len(ANGLE_NAMES))
    return centre + amp * np.sin(2 * np.pi * freq * t + rng.uniform(0, 2 * np.pi, len(ANGLE_NAMES)))


# -- sampling ----------------------------------------------------------------------------------------------
def test_tick_indices_60_to_20_hz_take_frame_3k_minus_1():
    np.testing.assert_array_equal(tick_indices(60, 60.0, 20.0), 3 * np.arange(1, 21) - 1)
    # n frames at f Hz last n/f s and give floor(n rate / f) ticks
    assert len(tick_indices(62, 60.0)) == 20 and len(tick_indices(63, 60.0)) == 21
    assert len(tick_indices(2, 60.0)) == 0
    # 30 Hz -> 20 Hz: the latest frame stamped strictly before k / 20 s, i.e. ceil(1.5 k) - 1
    np.testing.assert_array_equal(tick_indices(31, 30.0), np.ceil(1.5 * np.arange(1, 21)).astype(int) - 1)
    np.testing.assert_array_equal(tick_indices(5, 20.0), np.arange(5))
    with pytest.raises(ConfigError, match="rates must be > 0"):
        tick_indices(10, 60.0, 0.0)


def test_columns_are_the_twins_without_repetition():
    # ticks.csv carries the twin worker's stance and its balance and clearance last; a recording has none
    assert REPLAY_COLUMNS == tuple(c for c in TICK_COLUMNS
                                   if c != "repetition" and c not in STANCE + WORKER_MEASURES)
    trace = replay(_frames(30), 60.0)
    assert trace.table().shape == (10, len(REPLAY_COLUMNS))
    np.testing.assert_allclose(trace.t, np.arange(1, 11) / 20.0)
    assert replay(_frames(2), 60.0).table().shape == (0, len(REPLAY_COLUMNS))


# -- KWear ---------------------------------------------------------------------------------------------------
def test_kwear_equals_an_independent_recursion_over_the_rula_part_scores():
    frames = _frames(600)  # 10 s at 60 Hz -> 200 ticks
    params = KWearParams(t_max=60.0)  # faster wear, so V spans a good part of [0, 1)
    trace = replay(frames, 60.0, params)
    sampled = frames[2::3]
    res = rula(array_to_posture(sampled))
    g = np.asarray(part_scores(res), dtype=float).reshape(len(sampled), M)
    v, expect = np.zeros(M), []
    for row in g:  # eq. 4 tick by tick
        v = kwear_step(v, row, 1 / 20, params)
        expect.append(v)
    np.testing.assert_allclose(trace.v, expect, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(trace.g, g)
    np.testing.assert_array_equal(trace.grand, np.asarray(res.grand, dtype=float))
    for i, part in enumerate(RULA_PARTS):
        np.testing.assert_array_equal(trace.rula[:, i], getattr(res, part))
    assert 0.3 < trace.v_end.max() < 1.0 and np.all(np.diff(trace.v, axis=0) >= 0)


def test_constant_posture_follows_the_closed_form_of_eq_4():
    frames = np.tile(_frames(1)[0], (300, 1))
    trace = replay(frames, 60.0)
    g = trace.g[0]
    t = np.arange(1, 101)[:, None] / 20.0
    np.testing.assert_allclose(trace.v, 1.0 - np.exp(-g * t / P.C), rtol=1e-12)


def test_resting_ticks_recover_as_eq_5():
    frames = _frames(600)
    resting = np.arange(600) >= 300  # acting for 5 s, then resting
    trace = replay(frames, 60.0, resting=resting)
    assert trace.acting[:100].all() and not trace.acting[100:].any()
    np.testing.assert_allclose(trace.v[:100], replay(frames[:300], 60.0).v, rtol=0, atol=0)
    v0 = trace.v[99]
    t = np.arange(1, 101)[:, None] / 20.0
    np.testing.assert_allclose(trace.v[100:], v0 * np.exp(-P.r * t / P.C), rtol=1e-12)
    # a resting recording recovers from the state of the index it continues
    index = KWearIndex(P, {}, v0=np.full(M, 0.5))
    rest = replay(frames[:60], 60.0, resting=True, index=index)
    np.testing.assert_allclose(rest.v_end, 0.5 * np.exp(-P.r * 1.0 / P.C), rtol=1e-12)


def test_continuing_an_index_equals_one_replay():
    frames = _frames(600, seed=3)
    whole = replay(frames, 60.0)
    index = KWearIndex(P, {})
    first = replay(frames[:300], 60.0, index=index)
    second = replay(frames[300:], 60.0, index=index, t0=5.0)
    np.testing.assert_allclose(np.vstack([first.v, second.v]), whole.v, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.concatenate([first.t, second.t]), whole.t)
    assert index.ticks == whole.n


# -- dropouts ------------------------------------------------------------------------------------------------
def test_nan_frames_are_counted_dropouts_and_v_holds():
    frames = _frames(600)
    frames[[2, 5, 6, 7, 8, 100, 101, 102]] = np.nan  # ticks 1, 2, 3 (frames 2, 5, 8) and tick 34 (101)
    frames[200, 3] = np.nan  # one angle missing is a dropout as well (frame 200 = 3 * 67 - 1)
    frames[301] = np.nan  # not a tick's frame: never seen
    trace = replay(frames, 60.0)
    assert trace.dropouts == 5
    np.testing.assert_array_equal(np.flatnonzero(trace.dropout), [0, 1, 2, 33, 66])
    assert np.isnan(trace.g[trace.dropout]).all() and np.isfinite(trace.g[~trace.dropout]).all()
    assert np.isnan(trace.grand[trace.dropout]).all()
    assert np.isfinite(trace.v).all()
    np.testing.assert_array_equal(trace.v[:3], 0.0)  # no valid frame yet: no wear
    np.testing.assert_array_equal(trace.v[33], trace.v[32])
    np.testing.assert_array_equal(trace.v[66], trace.v[65])
    # the valid ticks wear exactly as without the dropouts' ticks
    clean = trace.g[~trace.dropout]
    v = np.zeros(M)
    for row in clean:
        v = kwear_step(v, row, 1 / 20, P)
    np.testing.assert_allclose(trace.v_end, v, rtol=0, atol=1e-15)
    index = KWearIndex(P, {})
    replay(frames, 60.0, index=index)
    assert index.dropouts == 5


def test_dropouts_while_resting_still_recover():
    frames = _frames(120)
    frames[:] = np.nan
    index = KWearIndex(P, {}, v0=np.full(M, 0.2))
    trace = replay(frames, 60.0, resting=True, index=index)
    assert trace.dropouts == 40 and np.isfinite(trace.v).all()
    np.testing.assert_allclose(trace.v_end, 0.2 * np.exp(-P.r * 2.0 / P.C), rtol=1e-12)


def test_bad_frames_are_clear_errors():
    with pytest.raises(RecordingError, match=r"\(n, 14\)"):
        replay(np.zeros((10, 5)), 60.0)
    with pytest.raises(ConfigError, match="resting"):
        replay(_frames(10), 60.0, resting=np.zeros(3, dtype=bool))


@pytest.fixture(scope="module")
def twin_segment():
    """A real twin segment: a1 of kwear-validation, measured with dropouts, played through the loop."""
    subject = Subject("T", variability_deg=0.0)
    cell = build_scene("kwear-validation", stature=subject.stature)
    rng = np.random.default_rng(4)
    track = WorkerTrack(Worker(subject), MocapStream(subject, rng, dropout_rate=0.05, dropout_frames=4))
    kwear = KWearIndex(P, {})
    plant = Plant(cell, track, kwear, mocap_rate=60.0, ergonomics_rate=20.0,
                  physics_dt=1 / 240)
    seg = track.start_action(track.worker.plan(cell, cell.actions["a1"], rng, action="a1"))
    assert plant.run_until(lambda: not track.busy, seg.motion.duration + 1.0)
    return plant, seg


def test_twin_dropouts_never_reach_kwear(twin_segment):
    plant, seg = twin_segment
    log = plant.log
    assert log.n == seg.n // 3
    assert np.isfinite(log.kwear).all() and log.kwear[-1].max() > 0
    dropped = log.column("dropout").astype(bool)
    assert plant.dropouts == dropped.sum() > 0
    # V holds on every acting dropout tick
    k = np.flatnonzero(dropped)
    k = k[k > 0]
    np.testing.assert_array_equal(log.kwear[k], log.kwear[k - 1])


def test_replay_of_the_measured_segment_equals_the_twin(twin_segment):
    plant, seg = twin_segment
    trace = replay(seg.measured, 60.0)
    assert trace.dropouts == plant.dropouts
    np.testing.assert_allclose(trace.v, plant.log.kwear, rtol=0, atol=1e-15)
    parts, grand, _ = score_frames(seg.measured)
    np.testing.assert_array_equal(trace.grand, grand[2::3][: trace.n])


# -- ergosim replay ------------------------------------------------------------------------------------------
def _cli(capsys, *argv):
    code = main(["replay", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_replay_command_writes_ticks_and_summary(tmp_path, capsys):
    out_dir = tmp_path / "out"
    code, out, err = _cli(capsys, str(BVH), "--out", str(out_dir))
    assert code == 0 and err == ""
    # no temporaries; the KWear plot as `ergosim run` writes it
    written = sorted(p.name for p in out_dir.iterdir())
    assert written == ["kwear_timeline_right.png", "summary.json", "ticks.csv"]
    rec = load_bvh(BVH)
    trace = replay(rec.array(ANGLE_NAMES), rec.rate_hz)
    lines = (out_dir / "ticks.csv").read_text().splitlines()
    assert lines[0].split(",") == list(REPLAY_COLUMNS) and len(lines) == 1 + 20 == 1 + trace.n
    table = np.loadtxt(out_dir / "ticks.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(table, trace.table(), rtol=1e-8, atol=1e-12)
    s = json.loads((out_dir / "summary.json").read_text())
    assert s["ticks"] == 20 and s["dropouts"] == 0 and s["frames"] == 31
    assert s["duration_s"] == pytest.approx(31 / 30) and s["ergonomics_rate_hz"] == 20.0
    assert s["kwear"]["worker"] is None and s["kwear"]["params"]["t_max"] == 240.0
    assert [s["kwear"]["final"][j] for j in KWEAR_JOINTS] == pytest.approx(trace.v_end, rel=1e-12)
    assert s["rula"]["grand"] == {"mean": pytest.approx(trace.grand.mean()), "max": trace.grand.max()}
    ua = trace.rula[:, RULA_PARTS.index("upper_arm")]
    assert s["rula"]["parts"]["upper_arm"] == {"mean": pytest.approx(ua.mean()), "max": ua.max()}
    # an overhead reach: the upper arm reaches RULA's top band (> 90 deg, raised shoulder, abducted)
    assert s["rula"]["parts"]["upper_arm"]["max"] >= 5
    assert "20 ticks at 20 Hz" in out and "0 dropouts" in out and str(out_dir.resolve()) in out


def test_replay_command_rate_and_stored_worker(tmp_path, capsys):
    store = ParamStore(tmp_path / "store")
    store.save(WorkerParams("W1", KWearParams(t_max=120.0)))
    code, out, _ = _cli(capsys, str(BVH), "--out", str(tmp_path / "o"), "--rate", "10",
                        "--worker", "W1", "--store", str(store.directory))
    assert code == 0 and "worker W1" in out
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    rec = load_bvh(BVH)
    trace = replay(rec.array(ANGLE_NAMES), rec.rate_hz, KWearParams(t_max=120.0), rate=10.0)
    assert s["ticks"] == trace.n == 10 and s["kwear"]["worker"] == "W1"
    assert [s["kwear"]["final"][j] for j in KWEAR_JOINTS] == pytest.approx(trace.v_end, rel=1e-12)


def _one_frame(tmp_path):
    text = BVH.read_text().split("MOTION")
    motion = text[1].strip().splitlines()
    path = tmp_path / "short.bvh"
    path.write_text(text[0] + "MOTION\nFrames: 1\n" + motion[1] + "\n" + motion[2] + "\n")
    return path


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("missing", "no such file"),
        ("directory", "is a directory, expected a BVH file"),
        ("malformed", "expected 'HIERARCHY'"),
        ("binary", "cannot read BVH file"),
        ("short", "shorter than one ergonomics tick"),
        ("worker_only", "--worker: give --worker and --store together"),
        ("unknown_worker", "no parameters for worker 'W9'"),
        ("rate", "--rate: must be a positive number of Hz"),
        ("fast_rate", "above the recording's frame rate 30 Hz"),
    ],
)
def test_replay_command_bad_inputs_are_one_line_errors(case, message, tmp_path, capsys):
    args = {
        "missing": [str(tmp_path / "nope.bvh")],
        "directory": [str(tmp_path)],
        "malformed": [str(DATA.parent / "test_worker_replay.py")],
        "binary": [str(tmp_path / "bin.bvh")],
        "short": [str(_one_frame(tmp_path))],
        "worker_only": [str(BVH), "--worker", "W1"],
        "unknown_worker": [str(BVH), "--worker", "W9", "--store", str(tmp_path)],
        "rate": [str(BVH), "--rate", "0"],
        "fast_rate": [str(BVH), "--rate", "60"],
    }[case]
    (tmp_path / "bin.bvh").write_bytes(bytes(range(128, 256)))
    out_dir = tmp_path / "out"
    code, out, err = _cli(capsys, *args, "--out", str(out_dir))
    assert code == 2 and out == ""
    assert err.startswith("ergosim: error: ") and message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out_dir.exists()


def test_replay_command_unwritable_out_is_one_line_error(tmp_path, capsys):
    (tmp_path / "taken").write_text("a file, not a directory")
    code, out, err = _cli(capsys, str(BVH), "--out", str(tmp_path / "taken"))
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"ergosim: error: --out: {tmp_path / 'taken'} exists and is not a directory")
    assert (tmp_path / "taken").read_text() == "a file, not a directory"


@pytest.mark.slow
def test_replay_error_has_no_traceback_in_a_subprocess(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "ergosim.cli", "replay", str(tmp_path / "missing.bvh"),
                           "--out", str(tmp_path / "o")], check=False, capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip() == f"ergosim: error: {tmp_path / 'missing.bvh'}: no such file"
    assert proc.stdout == ""
