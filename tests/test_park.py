"""Where robots park: every bundled cell, with either robot, parks each robot where its closest point keeps
the cell's clearance from the worker's head, neck and chest (or says it cannot), touching nothing; the
skills come back there; the distances are MuJoCo's, measured again here."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from ergosim.scenes import build_scene, scene_names
from ergosim.scenes.park import HEAD_AND_CHEST, ParkRule, choose_park, robot_geoms


def _clearance(cell, robot: str) -> float:
    m, d = cell.model, cell.data
    cell.reset()
    mine = robot_geoms(m, cell.robot(robot).base)
    fromto = np.zeros(6)
    regions = [m.geom(r).id for r in HEAD_AND_CHEST]
    return min(mujoco.mj_geomDistance(m, d, a, r, 2.0, fromto) for a in mine for r in regions)


@pytest.mark.parametrize("model", ["panda", "ur5"])
@pytest.mark.parametrize("scene", scene_names())
def test_every_bundled_cell_parks_its_robot_clear_of_the_head_and_chest(scene, model):
    fields = {"robots.robot.model": model}
    if (scene, model) == ("multi-subject", "ur5"):
        # the Panda's base there holds the UR5's upper arm in the bench at its ready pose (test_ur5_runs,
        # docs/robots.md): the UR5 on its own mount
        fields["robots.robot.base"] = (0.62, 0.82, 0.85)
    cell = build_scene(scene, **fields)
    park = cell.parks["robot"]
    measured = _clearance(cell, "robot")
    assert measured == pytest.approx(park.clearance, abs=1e-9)
    np.testing.assert_allclose(cell.robot_home("robot"), park.q)
    np.testing.assert_allclose(cell.data.ctrl[cell.robot("robot").arm_ctrl], park.q)
    wanted = next(r.park_clearance for r in cell.config.robots if r.name == "robot")
    # every bundled cell keeps 0.5 m but kwear-validation, whose bench stands the Panda 0.505 m from the
    # chest: 0.45 m there
    assert wanted == (0.45 if scene == "kwear-validation" else 0.5)
    assert park.met and measured >= wanted
    # nothing touched: no contact between the robot and anything else at the home keyframe
    mujoco.mj_forward(cell.model, cell.data)
    mine = set(robot_geoms(cell.model, cell.robot("robot").base))
    assert not [c for c in cell.data.contact[:cell.data.ncon] if (c.geom1 in mine) != (c.geom2 in mine)
                and c.dist < -0.003]


def test_the_least_change_that_keeps_the_clearance():
    cell = build_scene("gearbox")
    h = cell.robot()
    m, d = cell.model, cell.data
    cell.reset()
    ranges = m.jnt_range[[m.joint(j).id for j in h.robot.arm_joints]]
    home, tuck = np.array(h.robot.home), np.array(h.robot.tuck)

    def park(clearance: float):
        return choose_park(m, d, h.arm_qpos, h.base, home, tuck, ranges[:, 0], ranges[:, 1],
                           ParkRule(clearance=clearance))

    ready = park(0.0)
    np.testing.assert_array_equal(ready.q, home)  # clearance 0: the ready pose as it is
    near, far = park(0.3), park(0.6)
    assert near.met and far.met and near.clearance >= 0.3 and far.clearance >= 0.6
    assert np.linalg.norm(near.q - home) <= np.linalg.norm(far.q - home)
    impossible = park(5.0)
    assert not impossible.met and impossible.clearance == pytest.approx(ready_clearance(cell))
    np.testing.assert_array_equal(impossible.q, home)


def ready_clearance(cell) -> float:
    m, d = cell.model, cell.data
    h = cell.robot()
    d.qpos[h.arm_qpos] = h.robot.home
    mujoco.mj_kinematics(m, d)
    regions = [m.geom(r).id for r in HEAD_AND_CHEST]
    fromto = np.zeros(6)
    mine = robot_geoms(m, h.base)
    out = min(mujoco.mj_geomDistance(m, d, a, r, 2.0, fromto) for a in mine for r in regions)
    cell.reset()
    return out


def test_park_clearance_is_a_cell_field():
    cell = build_scene("gearbox", **{"robots.robot.park_clearance": "0"})
    np.testing.assert_array_equal(cell.robot_home(), cell.robot().robot.home)
