"""The worker's in-hand turn (ergosim.twin.in_hand): the weld target's path from grasp to place pose."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from ergosim.twin.in_hand import InHandTurn, relative_pose, slerp


def _unit(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


@pytest.mark.parametrize("seed", range(6))
def test_slerp_equals_mujoco_quaternion_integration(seed):
    rng = np.random.default_rng(seed)
    qa, qb = _unit(rng), _unit(rng)
    s = np.linspace(0.0, 1.0, 9)
    out = slerp(qa, qb, s)
    qb_near = qb if qa @ qb >= 0 else -qb  # the shorter arc
    for si, q in zip(s, out, strict=True):
        dq, vel, ref = np.empty(4), np.empty(3), qa.copy()
        mujoco.mju_mulQuat(dq, qa * [1, -1, -1, -1], qb_near)
        mujoco.mju_quat2Vel(vel, dq, 1.0)
        mujoco.mju_quatIntegrate(ref, vel, si)
        np.testing.assert_allclose(q, ref, atol=1e-12)
    np.testing.assert_allclose(out[0], qa, atol=1e-12)
    np.testing.assert_allclose(out[-1], qb_near, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-12)


def test_slerp_of_equal_quaternions_stays_put():
    q = np.array([0.5, 0.5, -0.5, 0.5])
    np.testing.assert_allclose(slerp(q, q, np.linspace(0, 1, 4)), np.tile(q, (4, 1)), atol=1e-15)


def test_turn_moves_the_weld_along_a_minimum_jerk_path():
    model = mujoco.MjModel.from_xml_string("""
    <mujoco><worldbody><body name="a" mocap="true"/><body name="b"><freejoint/><geom size="0.01"/></body>
    </worldbody><equality><weld name="w" body1="a" body2="b"/></equality></mujoco>""")
    model.eq_data[0, 3:6] = [0.1, 0.0, 0.0]
    model.eq_data[0, 6:10] = [1.0, 0.0, 0.0, 0.0]
    pos1, quat1 = np.array([0.0, 0.2, 0.0]), np.array([np.cos(0.5), 0.0, 0.0, np.sin(0.5)])
    turn = InHandTurn(model, 0, pos1, quat1, start=10, end=20)
    turn(5)  # before the grasp: nothing moves
    np.testing.assert_allclose(model.eq_data[0, 3:6], [0.1, 0.0, 0.0])
    path = []
    for frame in range(10, 25):
        turn(frame)
        path.append(model.eq_data[0, 3:10].copy())
    path = np.array(path)
    np.testing.assert_allclose(path[0], [0.1, 0, 0, 1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(path[10, :3], pos1, atol=1e-15)
    np.testing.assert_allclose(path[10, 3:], quat1, atol=1e-12)
    np.testing.assert_allclose(path[11:], np.tile(path[10], (4, 1)))  # after the place frame: held
    mid = path[5]  # tau = 0.5: minimum jerk is half way, in position and in angle
    np.testing.assert_allclose(mid[:3], [0.05, 0.1, 0.0], atol=1e-12)
    assert 2 * np.arctan2(mid[6], mid[3]) == pytest.approx(0.5, abs=1e-12)


def test_relative_pose_inverts_composition():
    rng = np.random.default_rng(3)
    p1, q1, p2, q2 = rng.normal(size=3), _unit(rng), rng.normal(size=3), _unit(rng)
    rel_p, rel_q = relative_pose(p1, q1, p2, q2)
    r1 = np.empty(9)
    mujoco.mju_quat2Mat(r1, q1)
    np.testing.assert_allclose(p1 + r1.reshape(3, 3) @ rel_p, p2, atol=1e-12)
    back = np.empty(4)
    mujoco.mju_mulQuat(back, q1, rel_q)
    np.testing.assert_allclose(back * np.sign(back[0] * q2[0]), q2, atol=1e-12)
