"""BVH recordings: parser, skeleton mapping onto the canonical angles, exporter, round trip."""

from __future__ import annotations

import importlib.util
import itertools
from pathlib import Path

import mujoco
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from ergosim.errors import RecordingError
from ergosim.human import HumanModel, human_spec
from ergosim.human.joints import joint_spec
from ergosim.posture import ANGLE_NAMES, HUMAN_JOINTS
from ergosim.worker.bvh import Recording, load_bvh, read_bvh_text, save_bvh
from ergosim.worker.bvh_chains import CHAINS, compose
from ergosim.worker.bvh_euler import alternate_euler, euler_to_matrix, matrix_to_euler
from ergosim.worker.bvh_export import bvh_text, export_skeleton
from ergosim.worker.bvh_kinematics import joint_positions
from ergosim.worker.bvh_mapping import angles_to_frames, map_skeleton, segment_frames
from ergosim.worker.bvh_parse import parse_bvh_text

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).parents[1]

# Y-up, facing +Z (+X is the left), rest pose with the arms hanging (N-pose), generic/CMU names.
N_POSE = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Head
    {
      OFFSET 0 50 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 0 20 0
      }
    }
    JOINT RightArm
    {
      OFFSET -18 45 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT RightForeArm
      {
        OFFSET 0 -30 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT RightHand
        {
          OFFSET 0 -25 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 0 -18 0
          }
        }
      }
    }
    JOINT LeftArm
    {
      OFFSET 18 45 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftForeArm
      {
        OFFSET 0 -30 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT LeftHand
        {
          OFFSET 0 -25 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 0 -18 0
          }
        }
      }
    }
  }
}
MOTION
"""
N_POSE_JOINTS = ("Hips", "Spine", "Head", "RightArm", "RightForeArm", "RightHand", "LeftArm", "LeftForeArm",
                 "LeftHand")
# (channel settings {(joint, axis): deg}, expected canonical angles; every other angle is 0).
N_POSE_FRAMES = [
    ({}, {}),
    ({("RightArm", "X"): -90}, {"shoulder_flexion": 90}),
    ({("RightForeArm", "X"): -90}, {"elbow_flexion": 90}),
    ({("RightArm", "Z"): -60, ("LeftArm", "Z"): 60},
     {"shoulder_abduction": 60, "left_shoulder_abduction": 60}),
    ({("Spine", "X"): 20, ("Head", "X"): 30}, {"trunk_flexion": 20, "neck_flexion": 30}),
    ({("Hips", "Y"): 40, ("Spine", "Y"): -10}, {"trunk_rotation": -10}),
    ({("Hips", "X"): 10, ("Spine", "X"): 20}, {"trunk_flexion": 30}),
    ({("RightForeArm", "Y"): 45, ("RightHand", "Z"): 30, ("RightHand", "X"): 10, ("LeftHand", "Z"): -30},
     {"forearm_pronation": 45, "wrist_flexion": 30, "wrist_deviation": 10, "left_wrist_flexion": 30}),
    ({("Spine", "Z"): 15, ("Head", "Z"): 20}, {"trunk_lateral_bend": 15, "neck_lateral_bend": 20}),
]

# Z-up, facing -Y (+X is the left), T-pose rest, Xsens MVN names with a two-segment spine and clavicles.
T_POSE = """HIERARCHY
ROOT Pelvis
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT L5
  {
    OFFSET 0 0 10
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT T8
    {
      OFFSET 0 0 35
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT Neck
      {
        OFFSET 0 0 20
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT Head
        {
          OFFSET 0 0 10
          CHANNELS 3 Zrotation Xrotation Yrotation
          End Site
          {
            OFFSET 0 0 20
          }
        }
      }
      JOINT RightShoulder
      {
        OFFSET -3 0 15
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT RightUpperArm
        {
          OFFSET -15 0 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          JOINT RightForeArm
          {
            OFFSET -30 0 0
            CHANNELS 3 Zrotation Xrotation Yrotation
            JOINT RightHand
            {
              OFFSET -25 0 0
              CHANNELS 3 Zrotation Xrotation Yrotation
              End Site
              {
                OFFSET -18 0 0
              }
            }
          }
        }
      }
      JOINT LeftShoulder
      {
        OFFSET 3 0 15
        CHANNELS 3 Zrotation Xrotation Yrotation
        JOINT LeftUpperArm
        {
          OFFSET 15 0 0
          CHANNELS 3 Zrotation Xrotation Yrotation
          JOINT LeftForeArm
          {
            OFFSET 30 0 0
            CHANNELS 3 Zrotation Xrotation Yrotation
            JOINT LeftHand
            {
              OFFSET 25 0 0
              CHANNELS 3 Zrotation Xrotation Yrotation
              End Site
              {
                OFFSET 18 0 0
              }
            }
          }
        }
      }
    }
  }
}
MOTION
"""
T_POSE_JOINTS = ("Pelvis", "L5", "T8", "Neck", "Head", "RightShoulder", "RightUpperArm", "RightForeArm",
                 "RightHand", "LeftShoulder", "LeftUpperArm", "LeftForeArm", "LeftHand")
_DOWN = {("RightUpperArm", "Y"): -90, ("LeftUpperArm", "Y"): 90}  # T-pose -> arms hanging
T_POSE_FRAMES = [
    ({}, {"shoulder_abduction": 90, "left_shoulder_abduction": 90}),
    (_DOWN, {}),
    ({**_DOWN, ("L5", "X"): 30, ("T8", "X"): 15}, {"trunk_flexion": 45}),
    ({**_DOWN, ("RightShoulder", "Y"): 10}, {"shoulder_elevation": 10}),
    ({**_DOWN, ("RightUpperArm", "Y"): -60}, {"shoulder_abduction": 30}),
]


def _motion(joints, frames, order="ZXY", root_height=95.0) -> str:
    """MOTION lines: joints have 3 rotation channels in ``order`` (root: 3 positions first)."""
    rows = []
    for setting, _ in frames:
        row = []
        for j in joints:
            zxy = {ax: setting.get((j, ax), 0.0) for ax in "ZXY"}
            r = euler_to_matrix(np.deg2rad([zxy["Z"], zxy["X"], zxy["Y"]]), "ZXY")
            angles = np.rad2deg(matrix_to_euler(r, order))
            row += ([0.0, root_height, 0.0] if j == joints[0] else []) + list(angles)
        rows.append(" ".join(f"{x:.6f}" for x in row))
    return f"Frames: {len(frames)}\nFrame Time: 0.0333333\n" + "\n".join(rows) + "\n"


def _assert_frames(rec: Recording, frames, tol: float = 0.5) -> None:
    for k, (_, expected) in enumerate(frames):
        for name, value in rec.angles.items():
            assert value[k] == pytest.approx(expected.get(name, 0.0), abs=tol), (k, name)


def test_euler_orders_match_scipy_and_invert():
    rng = np.random.default_rng(0)
    ang = rng.uniform(-np.pi, np.pi, (200, 3)) * np.array([1.0, 0.5, 1.0])
    for order in ("".join(p) for p in itertools.permutations("XYZ")):
        r = euler_to_matrix(ang, order)
        np.testing.assert_allclose(r, Rotation.from_euler(order, ang).as_matrix(), atol=1e-12)
        np.testing.assert_allclose(matrix_to_euler(r, order), ang, atol=1e-9)
        np.testing.assert_allclose(euler_to_matrix(alternate_euler(ang), order), r, atol=1e-12)
        lock = ang.copy()
        lock[:, 1] = np.pi / 2
        e = matrix_to_euler(euler_to_matrix(lock, order), order, first_hint=0.25)
        np.testing.assert_allclose(e[:, 0], 0.25)
        np.testing.assert_allclose(euler_to_matrix(e, order), euler_to_matrix(lock, order), atol=1e-12)


def test_hand_written_n_pose_gives_known_angles():
    rec = read_bvh_text(N_POSE + _motion(N_POSE_JOINTS, N_POSE_FRAMES), "npose.bvh")
    assert rec.n_frames == len(N_POSE_FRAMES) and rec.rate_hz == 30.0
    assert set(rec.angles) == set(HUMAN_JOINTS)
    _assert_frames(rec, N_POSE_FRAMES, tol=1e-6)
    assert rec.mapping == {
        "pelvis": "Hips", "thorax": "Spine", "head": "Head",
        "right_upper_arm": "RightArm", "right_forearm": "RightForeArm", "right_hand": "RightHand",
        "left_upper_arm": "LeftArm", "left_forearm": "LeftForeArm", "left_hand": "LeftHand",
    }


def test_pelvis_trunk_reference_excludes_hip_flexion():
    rec = read_bvh_text(N_POSE + _motion(N_POSE_JOINTS, N_POSE_FRAMES), trunk_reference="pelvis")
    assert rec.angles["trunk_flexion"][6] == pytest.approx(20.0, abs=1e-6)  # vertical reference: 30
    assert rec.angles["trunk_rotation"][5] == pytest.approx(-10.0, abs=1e-6)


@pytest.mark.parametrize("order", ["XYZ", "YXZ", "ZYX", "YZX", "XZY"])
def test_any_rotation_order(order):
    text = N_POSE.replace("Zrotation Xrotation Yrotation", " ".join(f"{a}rotation" for a in order))
    rec = read_bvh_text(text + _motion(N_POSE_JOINTS, N_POSE_FRAMES, order))
    _assert_frames(rec, N_POSE_FRAMES, tol=1e-4)


def test_xsens_t_pose_z_up_with_clavicles():
    rec = read_bvh_text(T_POSE + _motion(T_POSE_JOINTS, T_POSE_FRAMES, root_height=0.0), "mvn.bvh")
    _assert_frames(rec, T_POSE_FRAMES, tol=1e-6)
    assert rec.mapping["thorax"] == "T8" and rec.mapping["pelvis"] == "Pelvis"
    assert rec.mapping["right_clavicle"] == "RightShoulder"
    assert rec.mapping["right_upper_arm"] == "RightUpperArm"


def test_daz_friendly_names():
    names = {"Hips": "hip", "Spine": "chest", "Head": "head", "RightArm": "rShoulder",
             "RightForeArm": "rElbow", "RightHand": "rHand", "LeftArm": "lShoulder", "LeftForeArm": "lElbow",
             "LeftHand": "lHand"}
    text = N_POSE + _motion(N_POSE_JOINTS, N_POSE_FRAMES)
    for old in sorted(names, key=len, reverse=True):
        text = text.replace(f" {old}\n", f" {names[old]}\n")
    rec = read_bvh_text(text)
    assert rec.mapping == {role: names[old] for role, old in zip(
        ("pelvis", "thorax", "head", "right_upper_arm", "right_forearm", "right_hand", "left_upper_arm",
         "left_forearm", "left_hand"), N_POSE_JOINTS, strict=True)}
    _assert_frames(rec, N_POSE_FRAMES, tol=1e-6)


def test_name_map_and_missing_roles():
    text = (N_POSE + _motion(N_POSE_JOINTS, N_POSE_FRAMES)).replace("RightForeArm", "r_elbow_seg")
    with pytest.raises(RecordingError, match="right_forearm") as err:
        read_bvh_text(text, "odd.bvh")
    assert str(err.value).startswith("odd.bvh: ")
    rec = read_bvh_text(text, name_map={"right_forearm": "r_elbow_seg"})
    _assert_frames(rec, N_POSE_FRAMES, tol=1e-6)
    with pytest.raises(RecordingError, match="unknown role 'elbow'"):
        read_bvh_text(text, name_map={"elbow": "r_elbow_seg"})
    with pytest.raises(RecordingError, match="does not have"):
        read_bvh_text(text, name_map={"right_forearm": "Nope"})
    with pytest.raises(RecordingError, match="is not below"):
        read_bvh_text(text, name_map={"right_forearm": "LeftForeArm"})


def test_namespaced_names_and_no_left_arm():
    body = N_POSE.split("    JOINT LeftArm", maxsplit=1)[0] + "  }\n}\nMOTION\n"
    joints = N_POSE_JOINTS[:6]
    text = (body + _motion(joints, N_POSE_FRAMES[:3])).replace("JOINT ", "JOINT mixamorig:")
    rec = read_bvh_text(text)
    assert rec.mapping["right_hand"] == "mixamorig:RightHand"
    assert set(rec.angles) == set(ANGLE_NAMES)
    assert rec.array().shape == (3, 14)
    with pytest.raises(RecordingError, match="left_shoulder_flexion"):
        rec.array(HUMAN_JOINTS)


def _ranges(name: str) -> st.SearchStrategy[float]:
    lo, hi = joint_spec(name).range_deg
    if name.endswith("shoulder_abduction"):  # +-90 deg exactly is the chain's gimbal lock, tested apart
        return st.one_of(st.floats(lo, 89.0), st.floats(91.0, hi))
    return st.floats(lo, hi)


POSTURE = st.fixed_dictionaries({n: _ranges(n) for n in HUMAN_JOINTS})
COMBINED = {**{n: 0.0 for n in HUMAN_JOINTS}, "shoulder_flexion": 100.0, "shoulder_abduction": 60.0,
            "shoulder_rotation": -50.0, "forearm_pronation": 70.0, "wrist_flexion": 60.0,
            "wrist_deviation": -15.0,
            "left_shoulder_flexion": 150.0, "left_shoulder_abduction": 120.0, "left_shoulder_rotation": 60.0}


@settings(max_examples=60, deadline=None)
@given(st.lists(POSTURE, min_size=1, max_size=4))
@example([COMBINED])
def test_round_trip_within_half_degree(postures):
    angles = {n: np.array([p[n] for p in postures]) for n in HUMAN_JOINTS}
    rec = read_bvh_text(bvh_text(angles, 60.0))
    err = max(np.abs(rec.angles[n] - angles[n]).max() for n in HUMAN_JOINTS)
    assert err < 0.5
    assert err < 1e-3  # measured: ~1e-6 deg (6-decimal channels), amplified near the gimbal lock


@settings(max_examples=30, deadline=None)
@given(POSTURE, st.sampled_from([90.0, -90.0]), st.floats(-60.0, 120.0))
def test_round_trip_at_gimbal_lock_keeps_the_orientation(posture, abduction, previous_flexion):
    # Frame 0 is regular; at frame 1 the arm points straight sideways, where flexion and axial rotation turn
    # about the same axis: the flexion of frame 0 is held and the rotation absorbs the rest.
    angles = {n: np.array([posture[n], posture[n]]) for n in HUMAN_JOINTS}
    angles["shoulder_flexion"][0] = previous_flexion
    angles["shoulder_abduction"][1] = abduction
    rec = read_bvh_text(bvh_text(angles, 60.0))
    assert rec.angles["shoulder_flexion"][1] == pytest.approx(previous_flexion, abs=1e-3)
    for chain in ("shoulder", "elbow", "wrist"):
        want = compose(CHAINS[chain], {k: v[1] for k, v in angles.items()})
        got = compose(CHAINS[chain], {k: v[1] for k, v in rec.angles.items()})
        np.testing.assert_allclose(got, want, atol=1e-4)


@pytest.fixture(scope="module")
def human():
    model = human_spec(1.75).compile()
    return model, mujoco.MjData(model), HumanModel(model)


def test_exported_skeleton_matches_the_human_model(human):
    """Independent check of every sign: BVH joint centres and segment frames equal the MuJoCo human's."""
    model, data, hm = human
    rng = np.random.default_rng(3)
    angles = {n: rng.uniform(*joint_spec(n).range_deg, 20) for n in HUMAN_JOINTS}
    bvh = parse_bvh_text(bvh_text(angles, 60.0, stature=1.75))
    smap = map_skeleton(bvh)
    pos = np.einsum("ij,nkj->nki", smap.c, joint_positions(bvh)) / 100.0
    seg = segment_frames(bvh, smap)
    bodies = {"Spine": ("human_torso", "thorax"), "Neck": ("human_head", "head"),
              "RightShoulder": ("human_right_clavicle", "right_clavicle"),
              "LeftShoulder": ("human_left_clavicle", "left_clavicle")}
    for side in ("right", "left"):
        cap = side.capitalize()
        for bvh_name, seg_name in (("Arm", "upper_arm"), ("ForeArm", "forearm"), ("Hand", "hand")):
            bodies[cap + bvh_name] = (f"human_{side}_{seg_name}", f"{side}_{seg_name}")
    for f in range(20):
        hm.set_posture(data, {n: angles[n][f] for n in HUMAN_JOINTS})
        for bvh_name, (body, role) in bodies.items():
            np.testing.assert_allclose(pos[f, bvh.index(bvh_name)], data.body(body).xpos, atol=2e-4)
            np.testing.assert_allclose(seg[role][f], data.body(body).xmat.reshape(3, 3), atol=1e-7)
    frames = angles_to_frames(angles, 20)
    for role in frames:
        np.testing.assert_allclose(seg[role], frames[role], atol=1e-7)


def _script():
    spec = importlib.util.spec_from_file_location("make_test_bvh", ROOT / "scripts" / "make_test_bvh.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_committed_test_file_round_trip(tmp_path):
    script = _script()
    rec = load_bvh(DATA / "reach_overhead.bvh")
    truth = script.reach_angles()
    assert rec.rate_hz == script.RATE_HZ and rec.n_frames == script.N_FRAMES
    assert rec.source == str(DATA / "reach_overhead.bvh")
    for n in HUMAN_JOINTS:
        np.testing.assert_allclose(rec.angles[n], truth.get(n, 0.0), atol=0.5)
        np.testing.assert_allclose(rec.angles[n], truth.get(n, 0.0), atol=1e-4)
    # Export -> import -> export reproduces the channels; saving is deterministic.
    save_bvh(tmp_path / "again.bvh", dict(rec.angles), rec.rate_hz)
    again = parse_bvh_text((tmp_path / "again.bvh").read_text())
    original = parse_bvh_text((DATA / "reach_overhead.bvh").read_text())
    np.testing.assert_allclose(again.motion, original.motion, atol=1e-4)
    assert bvh_text(truth, 30.0) == bvh_text(truth, 30.0)
    assert not list(tmp_path.glob(".*.tmp"))


def test_load_is_deterministic_and_read_only():
    a, b = load_bvh(DATA / "reach_overhead.bvh"), load_bvh(DATA / "reach_overhead.bvh")
    for n in a.angles:
        assert np.array_equal(a.angles[n], b.angles[n])
    with pytest.raises(ValueError):
        a.angles["trunk_flexion"][0] = 1.0
    with pytest.raises(TypeError):
        a.angles["x"] = np.zeros(3)  # type: ignore[index]
    np.testing.assert_allclose(a.t[:3], [0.0, 1 / 30, 2 / 30])


def test_export_skeleton_proportions():
    joints = {j.name: j for j in export_skeleton(1.75)}
    assert joints["RightForeArm"].offset == pytest.approx((-0.186 * 175, 0.0, 0.0))
    assert joints["LeftHand"].offset == pytest.approx((0.146 * 175, 0.0, 0.0))
    tall = {j.name: j for j in export_skeleton(1.90)}
    assert tall["RightForeArm"].offset[0] == pytest.approx(-0.186 * 190)


def test_save_rejects_bad_angles(tmp_path):
    with pytest.raises(RecordingError, match="unknown angle names elbow"):
        save_bvh(tmp_path / "x.bvh", {"elbow": np.zeros(3)}, 60.0)
    with pytest.raises(RecordingError, match="NaN"):
        save_bvh(tmp_path / "x.bvh", {"elbow_flexion": np.array([1.0, np.nan])}, 60.0)
    with pytest.raises(RecordingError, match="shape"):
        save_bvh(tmp_path / "x.bvh", {"elbow_flexion": np.zeros(3), "wrist_flexion": np.zeros(2)}, 60.0)
    with pytest.raises(RecordingError, match="rate"):
        save_bvh(tmp_path / "x.bvh", {"elbow_flexion": np.zeros(3)}, 0.0)
    assert not (tmp_path / "x.bvh").exists()


def _good() -> str:
    return N_POSE + _motion(N_POSE_JOINTS, N_POSE_FRAMES[:3])


def _line_of(text: str, needle: str) -> int:
    return next(k + 1 for k, line in enumerate(text.splitlines()) if needle in line)


@pytest.mark.parametrize("case", ["truncated", "channel_count", "non_numeric", "no_motion", "unknown_channel",
                                  "bad_frames", "bad_frame_time", "unclosed", "not_bvh", "duplicate"])
def test_errors_name_file_and_line(case, tmp_path):
    text = _good()
    lines = text.splitlines()
    n_frames = _line_of(text, "Frames:")
    if case == "truncated":
        text, line, what = "\n".join(lines[:-1]) + "\n", len(lines) - 1, "truncated"
    elif case == "channel_count":
        lines[n_frames + 2] += " 1.0"
        text, line, what = "\n".join(lines), n_frames + 3, "31 values, expected 30"
    elif case == "non_numeric":
        lines[n_frames + 1] = lines[n_frames + 1].replace("95.000000", "9s.0", 1)
        text, line, what = "\n".join(lines), n_frames + 2, "'9s.0'"
    elif case == "no_motion":
        text, line, what = text.split("MOTION")[0], len(text.split("MOTION")[0].splitlines()), "no MOTION"
    elif case == "unknown_channel":
        line = _line_of(text, "CHANNELS 3")
        text, what = text.replace("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation", 1), "'Wrotation'"
    elif case == "bad_frames":
        text, line, what = text.replace("Frames: 3", "Frames: three"), n_frames, "Frames must be"
    elif case == "bad_frame_time":
        line = _line_of(text, "Frame Time")
        text, what = text.replace("Frame Time: 0.0333333", "Frame Time: 0"), "Frame Time must be"
    elif case == "unclosed":
        body = text.split("MOTION")[0].rstrip().rsplit("}", 1)[0]
        text, line, what = body, len(body.splitlines()), "file ends inside HIERARCHY"
    elif case == "not_bvh":
        text, line, what = "ROOT Hips\n{\n", 1, "expected 'HIERARCHY'"
    else:
        line = _line_of(text, "JOINT LeftArm")
        text, what = text.replace("JOINT LeftArm", "JOINT RightArm"), "used twice"
    path = tmp_path / "rec.bvh"
    path.write_text(text)
    with pytest.raises(RecordingError) as err:
        load_bvh(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}:{line}: "), msg
    assert what in msg and "\n" not in msg


def test_unreadable_file(tmp_path):
    with pytest.raises(RecordingError, match="no such file") as err:
        load_bvh(tmp_path / "missing.bvh")
    assert str(tmp_path / "missing.bvh") in str(err.value)
