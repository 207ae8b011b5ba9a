"""pinocchio (controller) against MuJoCo (plant): FK, Jacobians, IK."""

import mujoco
import numpy as np
import pytest

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import PandaKinematics
from ergosim.robot.model import panda_spec


@pytest.fixture(scope="module")
def kin():
    return PandaKinematics()


@pytest.fixture(scope="module")
def plant():
    m = panda_spec().compile()
    return m, mujoco.MjData(m)


def test_fk_matches_mujoco(kin, plant):
    m, d = plant
    rng = np.random.default_rng(1)
    frames = [f"panda_link{i}" for i in range(1, 8)] + ["panda_hand"]
    for _ in range(50):
        q = rng.uniform(kin.lower, kin.upper)
        d.qpos[:7] = q
        mujoco.mj_kinematics(m, d)
        p, r = kin.fk(q)
        np.testing.assert_allclose(p, d.site("panda_tcp").xpos, atol=1e-6)
        np.testing.assert_allclose(r, d.site("panda_tcp").xmat.reshape(3, 3), atol=1e-6)
        for f in frames:
            p, r = kin.fk(q, f)
            np.testing.assert_allclose(p, d.body(f).xpos, atol=1e-6)
            np.testing.assert_allclose(r, d.body(f).xmat.reshape(3, 3), atol=1e-6)


def test_jacobian_against_finite_differences(kin):
    rng = np.random.default_rng(2)
    eps = 1e-6
    for _ in range(10):
        q = rng.uniform(kin.lower + 0.01, kin.upper - 0.01)
        jac = kin.jacobian(q)
        p0, r0 = kin.fk(q)
        fd = np.zeros((6, 7))
        for i in range(7):
            dq = np.zeros(7)
            dq[i] = eps
            p1, r1 = kin.fk(q + dq)
            fd[:3, i] = (p1 - p0) / eps
            w = r1 @ r0.T  # small rotation in base-frame axes
            fd[3:, i] = np.array([w[2, 1] - w[1, 2], w[0, 2] - w[2, 0], w[1, 0] - w[0, 1]]) / (2 * eps)
        np.testing.assert_allclose(jac, fd, atol=1e-5)


def test_jacobian_matches_mujoco(kin, plant):
    m, d = plant
    q = np.array([0.3, -0.4, 0.2, -2.0, 0.3, 1.8, 0.5])
    d.qpos[:7] = q
    mujoco.mj_forward(m, d)
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, m.site("panda_tcp").id)
    np.testing.assert_allclose(kin.jacobian(q), np.vstack([jp, jr])[:, :7], atol=1e-9)


def test_ik_reaches_random_reachable_targets(kin):
    rng = np.random.default_rng(3)
    for _ in range(40):
        q_true = rng.uniform(kin.lower, kin.upper)
        pos, rot = kin.fk(q_true)
        res = solve_ik(kin, pos, rot, rng=rng, restarts=8)
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
