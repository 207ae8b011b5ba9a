"""The kinematic human: compiles, steps, signs match ergosim.posture, stature scaling, qpos <-> posture."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from ergosim.errors import ConfigError, ModelError
from ergosim.human import HumanModel, human_spec, humanoid_xml, segment_lengths
from ergosim.human.joints import DRIVEN_SPECS
from ergosim.posture import HUMAN_JOINTS, STANCE

MODELS = Path(__file__).resolve().parents[1] / "models" / "humanoid_upper"


@pytest.fixture(scope="module")
def human():
    model = human_spec().compile()
    return model, HumanModel(model)


def _pose(model, hm, **angles):
    data = mujoco.MjData(model)
    hm.set_posture(data, angles)
    return data


def test_committed_xml_matches_generator():
    assert (MODELS / "humanoid_upper.xml").read_text() == humanoid_xml(segment_lengths(1.75))


def test_scene_compiles_and_steps_one_second_without_warning():
    model = mujoco.MjModel.from_xml_path(str(MODELS / "scene.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    HumanModel(model).set_posture(data, {"shoulder_flexion": 70.0, "trunk_rotation": 20.0})
    q0 = data.qpos.copy()
    for _ in range(int(1.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    assert all(w.number == 0 for w in data.warning)
    assert np.all(np.isfinite(data.qpos))
    # gravity-compensated and damped: the undriven human stays where it was put
    assert np.abs(data.qpos - q0).max() < 1e-6


def test_structure(human):
    model, hm = human
    names = {model.joint(i).name for i in range(model.njnt)}
    driven = {j.name for j in DRIVEN_SPECS}
    assert names == set(HUMAN_JOINTS) | set(STANCE) | driven
    slides = {"pelvis_x", "pelvis_y", "pelvis_shift", "pelvis_drop"}
    for i in range(model.njnt):
        kind = mujoco.mjtJoint.mjJNT_SLIDE if model.joint(i).name in slides else mujoco.mjtJoint.mjJNT_HINGE
        assert model.jnt_type[i] == kind
    assert model.nu == 0
    assert np.all(model.geom_contype == 0) and np.all(model.geom_conaffinity == 0)
    assert np.all(model.jnt_limited == 1)
    base = model.body("human_base")
    assert base.jntnum[0] == 0 and model.body_parentid[base.id] == 0 and not base.pos.any()
    pelvis = model.body("human_pelvis")
    assert model.body_parentid[pelvis.id] == base.id
    assert model.body_pos[pelvis.id][2] == pytest.approx(0.530 * 1.75)
    for site in ("human_hand_right", "human_hand_left", "human_eyes"):
        assert model.site(site).id >= 0


def _gaze(data, model):
    return data.site_xmat[model.site("human_eyes").id].reshape(3, 3)[:, 0]


ELBOW90 = {"elbow_flexion": 90.0, "left_elbow_flexion": 90.0}


@pytest.mark.parametrize(
    ("angles", "base", "probe", "axis", "sign"),
    [
        ({"trunk_flexion": 30}, {}, "eyes", 0, +1),
        ({"trunk_lateral_bend": 20}, {}, "eyes", 1, -1),  # bend to the right
        ({"trunk_rotation": 30}, {}, "hand_right", 0, +1),  # twist left: right side comes forward
        ({"neck_flexion": 30}, {}, "eyes", 2, -1),
        ({"neck_lateral_bend": 30}, {}, "eyes", 1, -1),
        ({"neck_rotation": 30}, {}, "gaze", 1, +1),  # look left
        ({"shoulder_elevation": 20}, {}, "hand_right", 2, +1),
        ({"shoulder_flexion": 60}, {}, "hand_right", 0, +1),
        ({"shoulder_flexion": -30}, {}, "hand_right", 0, -1),
        ({"shoulder_abduction": 60}, {}, "hand_right", 1, -1),  # right arm out to the right
        ({"left_shoulder_abduction": 60}, {}, "hand_left", 1, +1),
        ({"shoulder_rotation": 40}, ELBOW90, "hand_right", 1, +1),  # internal: forearm to the belly
        ({"left_shoulder_rotation": 40}, ELBOW90, "hand_left", 1, -1),
        ({"elbow_flexion": 60}, {}, "hand_right", 0, +1),
        ({"wrist_flexion": 40}, {}, "hand_right", 1, +1),  # towards the palm, which faces the midline
        ({"left_wrist_flexion": 40}, {}, "hand_left", 1, -1),
        ({"wrist_deviation": 25}, {}, "hand_right", 0, -1),  # ulnar: towards the little finger (back)
    ],
)
def test_signs_follow_posture_conventions(human, angles, base, probe, axis, sign):
    model, hm = human
    ref = _pose(model, hm, **base)
    moved = _pose(model, hm, **{**base, **angles})

    def read(d):
        if probe == "eyes":
            return hm.eye_pos(d)
        if probe == "gaze":
            return _gaze(d, model)
        return hm.hand_pos(d, probe.split("_")[1])

    assert sign * (read(moved)[axis] - read(ref)[axis]) > 0.01


def test_pronation_turns_palm_down_with_forearm_forward(human):
    model, hm = human
    d0 = _pose(model, hm, elbow_flexion=90)
    d1 = _pose(model, hm, elbow_flexion=90, forearm_pronation=80)
    hand = model.body("human_right_hand").id
    # palm offset of the grasp site relative to the wrist axis, in the world frame
    off0 = hm.hand_pos(d0) - d0.xpos[hand]
    off1 = hm.hand_pos(d1) - d1.xpos[hand]
    assert off0[1] > 0.015  # palm medial at mid-position
    assert off1[2] < off0[2] - 0.015  # palm turned down


def test_posture_round_trip(human):
    model, hm = human
    rng = np.random.default_rng(3)
    lo, hi = hm.range_deg.T
    angles = rng.uniform(lo, hi)
    data = mujoco.MjData(model)
    hm.set_angles(data, angles)
    post = hm.posture(data.qpos)
    assert set(post) == set(HUMAN_JOINTS)
    np.testing.assert_allclose([post[n] for n in HUMAN_JOINTS], angles, atol=1e-12)
    batch = hm.posture(np.stack([data.qpos, data.qpos]))
    assert batch["trunk_flexion"].shape == (2,)


@pytest.mark.parametrize("stature", [1.55, 1.95])
def test_stature_scaling(stature, human):
    nominal, hm0 = human
    model = human_spec(stature).compile()
    hm = HumanModel(model)
    d0, d = mujoco.MjData(nominal), mujoco.MjData(model)
    hm0.set_angles(d0, np.zeros(22))
    hm.set_angles(d, np.zeros(22))
    k = stature / 1.75
    pairs = [("human_right_upper_arm", "human_right_forearm"), ("human_right_forearm", "human_right_hand"),
             ("human_torso", "human_head")]
    for a, b in pairs:
        length = np.linalg.norm(d.xpos[model.body(a).id] - d.xpos[model.body(b).id])
        length0 = np.linalg.norm(d0.xpos[nominal.body(a).id] - d0.xpos[nominal.body(b).id])
        assert length == pytest.approx(k * length0, rel=2e-4)  # the MJCF rounds to 0.1 mm
    assert hm.eye_pos(d)[2] == pytest.approx(0.936 * stature, rel=1e-3)
    assert hm.shoulder_pos(d)[2] == pytest.approx(0.818 * stature, rel=1e-3)


def test_segment_scale_and_errors():
    s = segment_lengths(1.75, {"upper_arm": 1.1})
    assert s.upper_arm == pytest.approx(1.1 * 0.186 * 1.75)
    with pytest.raises(ConfigError, match="unknown segment scale"):
        segment_lengths(1.75, {"tail": 1.0})
    with pytest.raises(ConfigError, match="outside"):
        segment_lengths(3.0)


def test_attach_into_a_scene_keeps_canonical_names():
    parent = mujoco.MjSpec.from_string(
        '<mujoco><default><default class="visual"><geom group="2"/></default></default>'
        '<worldbody><body name="bench" pos="0.5 0 0.4"><geom type="box" size="0.3 0.5 0.02"/></body>'
        "</worldbody></mujoco>")
    frame = parent.worldbody.add_frame(pos=[0.0, 0.3, 0.0])
    frame.attach_body(human_spec(1.62, keyframe=None).body("human_base"), "", "")
    with pytest.warns(UserWarning, match="empty prefix"):
        model = parent.compile()
    hm = HumanModel(model)
    data = mujoco.MjData(model)
    hm.set_angles(data, np.zeros(22))
    assert hm.shoulder_pos(data)[1] < 0.3 and hm.eye_pos(data)[2] == pytest.approx(0.936 * 1.62, rel=1e-3)


def test_missing_human_is_a_model_error():
    with pytest.raises(ModelError, match="trunk_flexion"):
        HumanModel(mujoco.MjModel.from_xml_string("<mujoco><worldbody/></mujoco>"))
