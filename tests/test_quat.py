"""ergosim.quat, the one quaternion module: MuJoCo's wxyz, rerun's xyzw, against MuJoCo and scipy."""

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ergosim import quat


@pytest.fixture(scope="module")
def quats():
    q = np.random.default_rng(7).normal(size=(200, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def test_to_mat_is_mujocos_to_the_last_bit_one_by_one_and_batched(quats):
    batch = quat.to_mat(quats.reshape(20, 10, 4))
    assert batch.shape == (20, 10, 3, 3)
    for q, m in zip(quats, batch.reshape(-1, 3, 3), strict=True):
        ref = np.empty(9)
        mujoco.mju_quat2Mat(ref, q)
        assert np.array_equal(m, ref.reshape(3, 3)) and np.array_equal(quat.to_mat(q), m)
    scipy_mats = Rotation.from_quat(quat.wxyz_to_xyzw(quats).astype(float)).as_matrix()
    np.testing.assert_allclose(batch.reshape(-1, 3, 3), scipy_mats, atol=1e-6)  # float32 on the way
    with pytest.raises(ValueError, match="shape"):
        quat.to_mat(np.zeros(3))


def test_products_conjugates_and_rotations_against_scipy(quats):
    a, b = quats[:100], quats[100:]
    ab = quat.mul(a, b)
    ref = Rotation.from_quat(a[:, [1, 2, 3, 0]]) * Rotation.from_quat(b[:, [1, 2, 3, 0]])  # a ⊗ b: b, then a
    np.testing.assert_allclose(quat.to_mat(ab), ref.as_matrix(), atol=1e-12)
    for qa, qb, q in zip(a[:10], b[:10], ab[:10], strict=True):
        res = np.empty(4)
        mujoco.mju_mulQuat(res, qa, qb)
        np.testing.assert_allclose(q, res, atol=1e-15)
    np.testing.assert_allclose(quat.mul(a, quat.conj(a)), np.tile([1.0, 0, 0, 0], (100, 1)), atol=1e-15)
    v = np.array([0.3, -0.2, 0.9])
    for q in a[:10]:
        np.testing.assert_allclose(quat.rotate(q, v), quat.to_mat(q) @ v, atol=1e-15)
        angle = np.degrees(Rotation.from_quat(q[[1, 2, 3, 0]]).magnitude())
        assert quat.angle_deg(q) == pytest.approx(angle, abs=1e-6)


def test_yaw_and_roll_pitch_yaw():
    turn = quat.to_mat(np.array(quat.from_yaw_deg(90.0)))
    np.testing.assert_allclose(turn, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    rng = np.random.default_rng(3)
    for rpy in rng.uniform(-np.pi, np.pi, size=(20, 3)):
        ref = Rotation.from_euler("xyz", rpy).as_matrix()  # lower case: extrinsic, R = Rz Ry Rx
        np.testing.assert_allclose(quat.to_mat(quat.from_rpy(rpy)), ref, atol=1e-12)
        np.testing.assert_array_equal(quat.from_rpy(np.degrees(rpy), degrees=True),
                                      quat.from_rpy(np.radians(np.degrees(rpy))))


def test_mujoco_and_rerun_orders_convert_in_one_place(quats):
    xyzw = quat.wxyz_to_xyzw(quats)
    assert xyzw.dtype == np.float32 and np.array_equal(xyzw[:, 3], quats[:, 0].astype(np.float32))
    np.testing.assert_allclose(quat.xyzw_to_wxyz(xyzw), quats, atol=1e-7)
    np.testing.assert_array_equal(quat.xyzw_to_wxyz(quats[:, [1, 2, 3, 0]]), quats)
    with pytest.raises(ValueError, match="shape"):
        quat.xyzw_to_wxyz(np.zeros(5))


def test_from_mat_is_mujocos_inverse_of_to_mat(quats):
    for q in quats[:20]:
        back = quat.from_mat(quat.to_mat(q))
        np.testing.assert_allclose(back * np.sign(back[0] * q[0]), q, atol=1e-12)  # q and -q: one rotation
        assert np.array_equal(quat.from_mat(quat.to_mat(q).reshape(9)), back)


@pytest.mark.parametrize("axis_from", ["x", "y", "z"])
def test_from_axis_to_takes_the_local_axis_onto_the_direction(axis_from):
    src = np.eye(3)["xyz".index(axis_from)]
    targets = [np.eye(3)[i] * s for i in range(3) for s in (1, -1)]
    targets += list(np.random.default_rng(5).normal(size=(10, 3)))
    for axis in targets:
        q = quat.from_axis_to(axis_from, tuple(axis))
        assert np.linalg.norm(q) == pytest.approx(1.0)
        np.testing.assert_allclose(quat.to_mat(q) @ src, axis / np.linalg.norm(axis), atol=1e-12)
    # the principal cases are exact: a slot along y or z keeps the part's faces parallel to the host's
    np.testing.assert_array_equal(quat.from_axis_to("x", (1.0, 0, 0)), [1.0, 0, 0, 0])
    h = np.sqrt(0.5)
    np.testing.assert_allclose(quat.from_axis_to("x", (0, 1.0, 0)), [h, 0, 0, h], atol=0)
    np.testing.assert_allclose(quat.from_axis_to("x", (0, 0, 1.0)), [h, 0, -h, 0], atol=0)
