"""A synthetic two-repetition run in the kwear-validation workcell, saved to .rrd, read back with rerun."""

from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest
import rerun as rr
from scipy.spatial.transform import Rotation

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS
from ergosim.robot.model import model_dir
from ergosim.robot.panda import PANDA
from ergosim.scenes import build_scene
from ergosim.viz import (
    RecordingReader,
    TwinRecorder,
    allocation_reason,
    default_body_groups,
    open_recording,
    scene_bodies,
)

TICKS = 300  # per repetition, 15 s at 20 Hz
V_TH = np.array([0.8, 0.8, 0.75, 0.8, 0.85])
DROPOUT = slice(40, 50)  # repetition 1: motion-capture frames lost


@pytest.fixture(scope="module")
def cell():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return build_scene("kwear-validation")


def _body_poses(cell, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(n, nbody, 3) positions and (n, nbody, 4) wxyz quaternions with every hinge swinging."""
    m, d = cell.model, mujoco.MjData(cell.model)
    hinge = [m.jnt_qposadr[j] for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
    pos, quat = np.empty((len(t), m.nbody, 3)), np.empty((len(t), m.nbody, 4))
    for k, tk in enumerate(t):
        d.qpos[:] = m.qpos0
        d.qpos[hinge] += 0.4 * np.sin(0.5 * tk + np.arange(len(hinge)))
        mujoco.mj_kinematics(m, d)
        pos[k], quat[k] = d.xpos, d.xquat
    return pos, quat


@pytest.fixture(scope="module")
def run(cell, tmp_path_factory):
    """Record a synthetic run; return the inputs and the path of the finished .rrd."""
    previous = rr.strict_mode()
    rr.set_strict_mode(True)  # misuse of the rerun API raises instead of logging a warning
    rng = np.random.default_rng(11)
    path = tmp_path_factory.mktemp("viz") / "run.rrd"
    names = [cell.model.body(b).name for b in range(cell.model.nbody)]
    logged = {"t": [], "rep": [], "pos": [], "quat": [], "angles": [], "rula": [], "grand": [], "kwear": [],
              "decisions": []}
    rec = open_recording(rrd=path)
    rec.flush_ticks = 250  # flushes mid-run, after each repetition's second batch, and at close
    rec.log_static(cell.model, v_th=V_TH, body_groups=default_body_groups(cell.model, cell.parts))
    for rep in range(2):
        t = 38.0 * rep + np.arange(TICKS) / 20.0
        pos, quat = _body_poses(cell, t)
        angles = rng.uniform(-30, 90, (TICKS, len(ANGLE_NAMES)))
        if rep == 1:
            angles[DROPOUT] = np.nan
            angles[200, 3] = np.nan
        rula = rng.integers(1, 5, (TICKS, len(RULA_PARTS))).astype(float)
        grand = rng.integers(1, 8, TICKS).astype(float)
        kwear = 1 - np.exp(-np.outer(t + 1, [0.02, 0.01, 0.03, 0.005, 0.004]))
        for half in (slice(0, TICKS // 2), slice(TICKS // 2, TICKS)):  # two batches per repetition
            rec.log_ticks(rep, t[half], pos[half], quat[half], names, angles[half], rula[half], grand[half],
                          kwear[half])
        for k, action in enumerate(("a1", "a2", "a3")):
            v_hat = {a: rng.uniform(0.2, 1.0, 5) for a in ("a1", "a2", "a3")}
            costs = {(a, ag): float(rng.uniform(0, 100)) for a in v_hat for ag in ("human", "robot")}
            agent = min(("human", "robot"), key=lambda ag, a=action: costs[a, ag])
            reason = allocation_reason((action, agent), v_hat=v_hat, costs=costs, v_th=V_TH)
            tk = 38.0 * rep + 2.0 + 4.0 * k
            rec.log_decision(tk, rep, kwear[40 * k], v_hat, costs, (action, agent), reason)
            logged["decisions"].append((tk, v_hat, costs, reason))
        for key, value in zip(("t", "pos", "quat", "angles", "rula", "grand", "kwear"),
                              (t, pos, quat, angles, rula, grand, kwear), strict=True):
            logged[key].append(value)
        logged["rep"].append(np.full(TICKS, rep))
    rec.close()
    rr.set_strict_mode(previous)
    arrays = {k: np.concatenate(v) for k, v in logged.items() if k != "decisions"}
    return path, arrays, logged["decisions"], rec.body_entities


@pytest.fixture(scope="module")
def reader(run):
    return RecordingReader(run[0])


def test_recording_passes_rerun_rrd_verify(run):
    exe = Path(sys.executable).with_name("rerun")
    exe = str(exe) if exe.exists() else shutil.which("rerun")
    assert exe, "the rerun CLI (from rerun-sdk) is not on this interpreter's path"
    result = subprocess.run([exe, "rrd", "verify", str(run[0])], capture_output=True, text=True, timeout=120,
                            check=False)
    assert result.returncode == 0, result.stderr
    assert "1 file verified without error" in result.stdout + result.stderr


def test_every_moving_body_has_its_world_transform(cell, run, reader):
    _, logged, _, entities = run
    bodies = scene_bodies(cell.model, default_body_groups(cell.model, cell.parts))
    static = {b.name for b in bodies if b.static_pose is not None}
    assert entities["panda_link3"] == "world/robot/panda_link3"
    assert entities["human_right_forearm"] == "world/human/right_forearm"
    assert entities["J"] == "world/parts/J"
    for b in range(cell.model.nbody):
        name = cell.model.body(b).name
        entity = entities[name]
        if name in static:
            assert "Transform3D:translation" in reader.components(entity, static=True)
            np.testing.assert_allclose(reader.static(entity, "Transform3D:translation")[0],
                                       logged["pos"][0, b], atol=1e-6)
            continue
        t, trans, quat = reader.transforms(entity)
        np.testing.assert_allclose(t, logged["t"], atol=1e-9)
        np.testing.assert_allclose(trans, logged["pos"][:, b], atol=1e-6)
        # rerun's xyzw is MuJoCo's wxyz reordered: the same rotation
        mats = np.empty((len(t), 9))
        for k in range(len(t)):
            mujoco.mju_quat2Mat(mats[k], logged["quat"][k, b])
        np.testing.assert_allclose(Rotation.from_quat(quat).as_matrix(), mats.reshape(-1, 3, 3), atol=1e-6)


def test_kwear_and_rula_series_equal_what_was_logged(reader, run):
    _, logged, _, _ = run
    for j, joint in enumerate(KWEAR_JOINTS):
        t, v = reader.scalars(f"ergonomics/kwear/{joint}")
        np.testing.assert_allclose(t, logged["t"], atol=1e-9)
        np.testing.assert_array_equal(v, logged["kwear"][:, j])
        trep, _ = reader.column(f"ergonomics/kwear/{joint}", "Scalars:scalars", timeline="repetition")
        assert np.array_equal(np.sort(trep), logged["rep"])
    for p, part in enumerate(RULA_PARTS):
        np.testing.assert_array_equal(reader.scalars(f"ergonomics/rula/{part}")[1], logged["rula"][:, p])
    np.testing.assert_array_equal(reader.scalars("ergonomics/rula/grand")[1], logged["grand"])


def test_dropouts_leave_gaps_not_values(reader, run):
    _, logged, _, _ = run
    for i, name in enumerate(ANGLE_NAMES):
        t, v = reader.scalars(f"ergonomics/angles/{name}")
        ok = np.isfinite(logged["angles"][:, i])
        assert len(v) == ok.sum() == 2 * TICKS - 10 - (name == ANGLE_NAMES[3])
        np.testing.assert_allclose(t, logged["t"][ok], atol=1e-9)
        np.testing.assert_array_equal(v, logged["angles"][ok, i])


def test_thresholds_span_every_flush(reader):
    for j, joint in enumerate(KWEAR_JOINTS):
        t, v = reader.scalars(f"ergonomics/kwear_threshold/{joint}")
        np.testing.assert_array_equal(v, V_TH[j])
        end = (TICKS - 1) / 20.0
        np.testing.assert_allclose(t, [0.0, end, 38.0, 38.0 + end], atol=1e-9)  # one flush per repetition


def test_decisions_hold_the_reason_predictions_and_costs(reader, run):
    _, _, decisions, _ = run
    t, texts = reader.texts("allocation/log")
    np.testing.assert_allclose(t, [d[0] for d in decisions])
    assert texts == [d[3] for d in decisions]
    assert all(" → " in s and "KWear" in s for s in texts)
    for action in ("a1", "a2", "a3"):
        for j, joint in enumerate(KWEAR_JOINTS):
            _, v = reader.scalars(f"allocation/v_hat/{action}/{joint}")
            np.testing.assert_allclose(v, [d[1][action][j] for d in decisions])
        for agent in ("human", "robot"):
            _, c = reader.scalars(f"allocation/costs/{action}/{agent}")
            np.testing.assert_allclose(c, [d[2][action, agent] for d in decisions])
    assert len(reader.scalars("allocation/v_now/shoulder")[1]) == len(decisions)


def test_panda_meshes_are_the_model_files(reader):
    entity = "world/robot/panda_link3/link3_0"
    (blob,) = reader.static(entity, "Asset3D:blob")
    assert bytes(blob) == (model_dir(PANDA) / "assets" / "link3_0.obj").read_bytes()
    assert reader.static(entity, "Asset3D:media_type") == ["model/obj"]
    assert "Transform3D:translation" in reader.components(entity, static=True)


def test_human_capsules_are_centred_where_mujoco_has_them(cell, reader):
    m = cell.model
    g = m.geom("human_right_forearm").id
    entity = "world/human/right_forearm/capsules"
    start = np.array(reader.static(entity, "Capsules3D:translations")[0])
    quat = np.array(reader.static(entity, "Capsules3D:quaternions")[0])
    length = reader.static(entity, "Capsules3D:lengths")[0]
    centre = start + Rotation.from_quat(quat).apply([0.0, 0.0, length / 2])
    np.testing.assert_allclose(centre, m.geom_pos[g], atol=1e-6)
    assert length == pytest.approx(2 * m.geom_size[g, 1])


def test_recording_carries_the_blueprint(reader):
    assert reader.has_blueprint and reader.application_ids == ["ergosim"]


def test_bad_calls_are_refused(cell, tmp_path):
    with open_recording(rrd=tmp_path / "bad.rrd") as rec:
        args = (np.zeros(2), np.zeros((2, 1, 3)), np.tile([1.0, 0, 0, 0], (2, 1, 1)), ["J"],
                np.zeros((2, 14)), np.zeros((2, 7)), np.zeros(2), np.zeros((2, 5)))
        with pytest.raises(RuntimeError, match="log_static must be called before log_ticks"):
            rec.log_ticks(0, *args)
        with pytest.raises(ValueError, match=r"v_th must have shape \(5,\)"):
            rec.log_static(cell.model, v_th=np.zeros(4), body_groups={})
        rec.log_static(cell.model, v_th=V_TH, body_groups={})
        with pytest.raises(ValueError, match=r"kwear must have shape \(2, 5\)"):
            rec.log_ticks(0, *args[:-1], np.zeros((2, 4)))
        with pytest.raises(ValueError, match="bodies the model does not have: elbow"):
            rec.log_ticks(0, *args[:3], ["elbow"], *args[4:])
        rec.log_ticks(0, *args)
    assert RecordingReader(tmp_path / "bad.rrd").scalars("ergonomics/kwear/neck")[1].tolist() == [0.0, 0.0]


def test_disabled_recorder_is_silent():
    rec = TwinRecorder(None)
    assert not rec.enabled and rec.body_entities == {}
    rec.close()


def test_unnamed_bodies_are_recorded_by_their_id(tmp_path):
    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body pos='0 0 1'><freejoint/><geom type='box' size='.1 .1 .1'/></body>"
        "</worldbody></mujoco>")
    names = [model.body(b).name for b in range(model.nbody)]
    assert names == ["world", ""]
    pos = np.array([[[0, 0, 0], [0.1, 0.2, 0.3]], [[0, 0, 0], [0.4, 0.5, 0.6]]])
    quat = np.tile([1.0, 0, 0, 0], (2, 2, 1))
    with open_recording(rrd=tmp_path / "unnamed.rrd") as rec:
        rec.log_static(model, v_th=V_TH, body_groups={})
        rec.log_ticks(0, np.array([0.0, 0.05]), pos, quat, names, np.zeros((2, 14)), np.ones((2, 7)),
                      np.ones(2), np.zeros((2, 5)))
    _, xyz, _ = RecordingReader(tmp_path / "unnamed.rrd").transforms("world/scene/body1")
    np.testing.assert_allclose(xyz, pos[:, 1], atol=1e-6)
