"""pinocchio (controller) against MuJoCo (plant) for every bundled robot: FK of every link and the TCP,
Jacobians against finite differences and against MuJoCo's, IK."""

import mujoco
import numpy as np
import pytest

from ergosim.robot import ArmKinematics, get_robot, robot_names, robot_spec
from ergosim.robot.assets import erd_file
from ergosim.robot.ik import solve_ik
from ergosim.robot.urdf import read_urdf


@pytest.fixture(scope="module", params=robot_names())  # every registered robot
def robot(request):
    return get_robot(request.param)


@pytest.fixture(scope="module")
def kin(robot):
    return ArmKinematics(robot)


@pytest.fixture(scope="module")
def plant(robot):
    m = robot_spec(robot).compile()
    return m, mujoco.MjData(m)


def test_fk_matches_mujoco(robot, kin, plant):
    m, d = plant
    n = kin.nq
    links = [read_urdf(erd_file(robot.urdf)).joint(j).child for j in robot.arm_joints]
    rng = np.random.default_rng(1)
    for _ in range(50):
        q = rng.uniform(kin.lower, kin.upper)
        d.qpos[:n] = q
        mujoco.mj_kinematics(m, d)
        p, r = kin.fk(q)
        np.testing.assert_allclose(p, d.site(robot.tcp_site).xpos, atol=1e-6)
        np.testing.assert_allclose(r, d.site(robot.tcp_site).xmat.reshape(3, 3), atol=1e-6)
        for f in (*links, robot.hand):
            p, r = kin.fk(q, f)
            np.testing.assert_allclose(p, d.body(f).xpos, atol=1e-6)
            np.testing.assert_allclose(r, d.body(f).xmat.reshape(3, 3), atol=1e-6)


def test_jacobian_against_finite_differences(kin):
    rng = np.random.default_rng(2)
    eps = 1e-6
    n = kin.nq
    for _ in range(10):
        q = rng.uniform(kin.lower + 0.01, kin.upper - 0.01)
        jac = kin.jacobian(q)
        p0, r0 = kin.fk(q)
        fd = np.zeros((6, n))
        for i in range(n):
            dq = np.zeros(n)
            dq[i] = eps
            p1, r1 = kin.fk(q + dq)
            fd[:3, i] = (p1 - p0) / eps
            w = r1 @ r0.T  # small rotation in base-frame axes
            fd[3:, i] = np.array([w[2, 1] - w[1, 2], w[0, 2] - w[2, 0], w[1, 0] - w[0, 1]]) / (2 * eps)
        np.testing.assert_allclose(jac, fd, atol=1e-5)


def test_jacobian_matches_mujoco(robot, kin, plant):
    m, d = plant
    n = kin.nq
    q = kin.home + np.array([0.3, -0.4, 0.2, -0.3, 0.3, 0.2, 0.5])[:n]
    d.qpos[:n] = q
    mujoco.mj_forward(m, d)
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, m.site(robot.tcp_site).id)
    np.testing.assert_allclose(kin.jacobian(q), np.vstack([jp, jr])[:, :n], atol=1e-9)


@pytest.mark.slow
def test_ik_reaches_random_reachable_targets(kin):
    rng = np.random.default_rng(3)
    for _ in range(40):
        q_true = rng.uniform(kin.lower, kin.upper)
        pos, rot = kin.fk(q_true)
        # near a singularity the UR5's IK converges from only ~10 % of random starts: allow many
        res = solve_ik(kin, pos, rot, rng=rng, restarts=40)
        assert res.ok
        p, r = kin.fk(res.q)
        assert np.linalg.norm(p - pos) < 2e-3
        angle = np.degrees(np.arccos(np.clip((np.trace(r.T @ rot) - 1) / 2, -1, 1)))
        assert angle < 1.0
        assert kin.within_limits(res.q)


def test_ik_reports_unreachable(kin):
    res = solve_ik(kin, np.array([1.5, 0.0, 0.5]), np.eye(3))
    assert not res.ok and res.pos_error > 0.3
    assert kin.within_limits(res.q)


def test_reach_is_the_declared_one(robot, kin):
    """The farthest TCP from the first joint axis over random configurations stays within the datasheet
    reach plus the gripper (the datasheet reach is to the flange)."""
    rng = np.random.default_rng(4)
    shoulder = kin.fk(np.zeros(kin.nq), kin.model.frames[kin.model.getFrameId(robot.mount.link)].name)[0]
    far = max(np.linalg.norm(kin.fk(rng.uniform(kin.lower, kin.upper))[0][:2] - shoulder[:2])
              for _ in range(2000))
    assert robot.reach * 0.8 < far < robot.reach + 0.25
