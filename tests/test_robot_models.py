"""Every registered robot's MJCF (the Panda, the UR5): committed files = generator output, menagerie layout,
URDF numbers carried over, real visual meshes, opens in plain MuJoCo, home holds, actuators work."""

from pathlib import Path

import mujoco
import numpy as np
import pytest

from ergosim.robot import get_robot, robot_files, robot_names, robot_spec
from ergosim.robot.assets import erd_file
from ergosim.robot.model import model_dir, scene_xml
from ergosim.robot.urdf import read_urdf

ROBOTS = [get_robot(n) for n in robot_names()]  # every registered robot
IDS = [r.name for r in ROBOTS]


@pytest.fixture(scope="module", params=ROBOTS, ids=IDS)
def robot(request):
    return request.param


@pytest.fixture(scope="module")
def model(robot):
    return robot_spec(robot).compile()


@pytest.fixture(scope="module")
def urdf(robot):
    urdf = read_urdf(erd_file(robot.urdf))
    return robot.edit_urdf(urdf) if robot.edit_urdf else urdf


def test_bundled_robots_registered():
    assert {"panda", "ur5"} <= set(robot_names())


def test_committed_files_are_the_generator_output(robot):
    files = robot_files(robot)
    folder = model_dir(robot)
    assert (folder / f"{robot.name}.xml").read_text() == files.xml
    on_disk = {p.name for p in (folder / "assets").iterdir()}
    assert on_disk == set(files.assets)
    for name, blob in files.assets.items():
        assert (folder / "assets" / name).read_bytes() == blob, name
    assert (folder / "scene.xml").read_text() == scene_xml(robot.name)
    readme = (folder / "README.md").read_text()
    assert "## Source" in readme and "Licence" in readme and "## Derivation" in readme


def test_menagerie_layout(robot):
    text = (model_dir(robot) / f"{robot.name}.xml").read_text()
    assert '<compiler angle="radian" autolimits="true" meshdir="assets"/>' in text
    order = [text.index(f"<{tag}") for tag in ("compiler", "option", "default", "asset", "worldbody",
                                                 "equality", "actuator", "keyframe")]
    assert order == sorted(order)
    assert '<default class="visual">' in text and '<default class="collision">' in text
    assert 'group="2"' in text and 'group="3"' in text and '<key name="home"' in text


def test_named_elements(robot, model):
    for j in (*robot.arm_joints, *robot.finger_joints):
        assert model.joint(j).id >= 0
    for b in (robot.base, robot.hand, *robot.gripper.bodies):
        assert model.body(b).id >= 0
    assert model.site(robot.tcp_site).id >= 0
    assert model.actuator(robot.gripper_actuator).id == len(robot.arm_joints)
    assert [model.actuator(a).id for a in robot.arm_actuators] == list(range(len(robot.arm_joints)))
    assert model.keyframe("home").id == 0


def test_limits_and_inertias_from_urdf(robot, model, urdf):
    for name, act in zip(robot.arm_joints, robot.arm_actuators, strict=True):
        j = urdf.joint(name)
        np.testing.assert_allclose(model.jnt_range[model.joint(name).id], [j.lower, j.upper])
        np.testing.assert_allclose(model.actuator(act).forcerange, [-j.effort, j.effort])
        np.testing.assert_allclose(model.actuator(act).ctrlrange, [j.lower, j.upper])
        inertial = urdf.links[j.child].inertial
        assert model.body_mass[model.body(j.child).id] == pytest.approx(inertial.mass)
        ixx, iyy, izz, ixy, ixz, iyz = inertial.inertia
        eig = np.linalg.eigvalsh([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        np.testing.assert_allclose(np.sort(model.body_inertia[model.body(j.child).id]), eig, rtol=1e-6)
    root = robot.recipe.root
    below = {root}
    for j in urdf.joints:  # the links of the model: the root and everything below it
        if j.parent in below:
            below.add(j.child)
    total = sum(urdf.links[n].inertial.mass for n in below if urdf.links[n].inertial)
    assert model.body_subtreemass[model.body(root).id] == pytest.approx(total)


def test_visual_class_holds_the_converted_visual_meshes(robot, model):
    visual = [g for g in range(model.ngeom) if model.geom_group[g] == 2 and model.geom_type[g] == 7]
    collision = [g for g in range(model.ngeom) if model.geom_group[g] == 3 and model.geom_type[g] == 7]
    assert len(visual) > len(collision) >= 6
    vis_faces = sum(model.mesh_facenum[model.geom_dataid[g]] for g in visual)
    col_faces = sum(model.mesh_facenum[model.geom_dataid[g]] for g in collision)
    assert vis_faces > 5 * col_faces  # the real visuals, not the coarse collision hulls
    colours = {tuple(np.round(model.mat_rgba[model.geom_matid[g]], 3)) for g in visual}
    assert len(colours) >= 2
    assert all(model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0 for g in visual)


@pytest.mark.parametrize("name", IDS)
def test_opens_in_plain_mujoco_from_any_folder(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for xml in ("scene.xml", f"{name}.xml"):
        m = mujoco.MjModel.from_xml_path(str(Path(model_dir(ROBOTS[IDS.index(name)])) / xml))
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, 0)
        mujoco.mj_step(m, d, 200)
        assert d.warning.number.sum() == 0 and np.isfinite(d.qpos).all()


def test_home_holds_and_gripper_closes(robot, model):
    n = len(robot.arm_joints)
    d = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, d, model.keyframe("home").id)
    mujoco.mj_step(model, d, 500)
    np.testing.assert_allclose(d.qpos[:n], robot.home, atol=1e-3)
    d.ctrl[n] = 0.0
    mujoco.mj_step(model, d, 500)
    assert d.qpos[n] < 1e-3 and abs(d.qpos[n] - d.qpos[n + 1]) < 1e-3
    assert d.warning.number.sum() == 0


def test_position_actuators_track_and_respect_effort(robot, model):
    n = len(robot.arm_joints)
    d = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, d, 0)
    target = np.array(robot.home) + np.array([0.3, 0.2, -0.2, 0.3, 0.4, -0.3, 0.5][:n])
    d.ctrl[:n] = target
    for _ in range(1000):
        mujoco.mj_step(model, d)
        assert np.all(np.abs(d.actuator_force[:n]) <= model.actuator_forcerange[:n, 1] + 1e-9)
    np.testing.assert_allclose(d.qpos[:n], target, atol=2e-3)
