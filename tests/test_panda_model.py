"""The generated Panda MJCF: committed file = generator output, URDF numbers carried over, actuators work."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from ergosim.robot.assets import panda_urdf
from ergosim.robot.mjcf import ARM_ACTUATORS, ARM_JOINTS, FINGER_JOINTS, GRIPPER_ACTUATOR, HOME_QPOS, TCP_SITE
from ergosim.robot.model import load_mjcf, panda_mjcf_text, panda_spec
from ergosim.robot.urdf import read_urdf

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def model():
    return panda_spec().compile()


@pytest.fixture(scope="module")
def urdf():
    return read_urdf(panda_urdf())


def test_committed_mjcf_is_the_generator_output():
    assert (ROOT / "models/panda/panda.xml").read_text() == panda_mjcf_text()


def test_menagerie_layout():
    text = (ROOT / "models/panda/panda.xml").read_text()
    assert '<compiler angle="radian" autolimits="true"/>' in text
    order = [text.index(f"<{tag}") for tag in ("compiler", "option", "default", "asset", "worldbody",
                                                 "equality", "actuator", "keyframe")]
    assert order == sorted(order)
    assert '<default class="visual">' in text and '<default class="collision">' in text
    assert 'group="2"' in text and 'group="3"' in text


def test_named_elements(model):
    for j in (*ARM_JOINTS, *FINGER_JOINTS):
        assert model.joint(j).id >= 0
    for b in [f"panda_link{i}" for i in range(8)] + ["panda_hand", "panda_leftfinger", "panda_rightfinger"]:
        assert model.body(b).id >= 0
    assert model.site(TCP_SITE).id >= 0
    assert model.actuator(GRIPPER_ACTUATOR).id == 7
    assert model.keyframe("home").id == 0


def test_limits_and_inertias_from_urdf(model, urdf):
    for name, act in zip(ARM_JOINTS, ARM_ACTUATORS, strict=True):
        j = urdf.joint(name)
        np.testing.assert_allclose(model.jnt_range[model.joint(name).id], [j.lower, j.upper])
        np.testing.assert_allclose(model.actuator(act).forcerange, [-j.effort, j.effort])
        np.testing.assert_allclose(model.actuator(act).ctrlrange, [j.lower, j.upper])
        inertial = urdf.links[j.child].inertial
        assert model.body_mass[model.body(j.child).id] == pytest.approx(inertial.mass)
        # principal moments are invariant: compare the eigenvalues of the URDF tensor
        ixx, iyy, izz, ixy, ixz, iyz = inertial.inertia
        eig = np.linalg.eigvalsh([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        np.testing.assert_allclose(np.sort(model.body_inertia[model.body(j.child).id]), eig, rtol=1e-6)
    total = sum(link.inertial.mass for link in urdf.links.values() if link.inertial)
    assert model.body_subtreemass[model.body("panda_link0").id] == pytest.approx(total)


def test_scene_loads_with_meshes_from_the_package():
    m = load_mjcf(ROOT / "models/panda/scene.xml")
    assert m.nmesh == 10 and m.nu == 8
    assert m.geom("floor").id >= 0


def test_home_holds_and_gripper_closes(model):
    d = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, d, model.keyframe("home").id)
    for _ in range(500):
        mujoco.mj_step(model, d)
    np.testing.assert_allclose(d.qpos[:7], HOME_QPOS, atol=1e-3)
    d.ctrl[7] = 0.0
    for _ in range(500):
        mujoco.mj_step(model, d)
    assert d.qpos[7] < 1e-3 and abs(d.qpos[7] - d.qpos[8]) < 1e-3
    assert d.warning.number.sum() == 0


def test_position_actuators_track_and_respect_effort(model):
    d = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, d, 0)
    target = np.array(HOME_QPOS) + np.array([0.3, 0.2, -0.2, 0.3, 0.4, -0.3, 0.5])
    d.ctrl[:7] = target
    for _ in range(1000):
        mujoco.mj_step(model, d)
        assert np.all(np.abs(d.actuator_force[:7]) <= model.actuator_forcerange[:7, 1] + 1e-9)
    np.testing.assert_allclose(d.qpos[:7], target, atol=2e-3)
