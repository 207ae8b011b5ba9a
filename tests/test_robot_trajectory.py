"""Straight lines and joint-space transits: the TCP speed caps of each segment kind, measured on the joint
trajectories with pinocchio forward kinematics (never read back from the parameters)."""

import numpy as np
import pinocchio as pin
import pytest

from ergosim.robot import ArmKinematics
from ergosim.robot.ik import solve_ik
from ergosim.robot.panda import PANDA
from ergosim.robot.trajectory import (
    CONTACT_SPEED,
    TRANSIT_SPEED,
    MotionLimits,
    Pose,
    line_trajectory,
    transit_trajectory,
)

DT = 0.002


@pytest.fixture(scope="module")
def kin():
    return ArmKinematics(PANDA)


def _tcp(kin, traj):
    poses = [kin.fk(q) for q in traj]
    return np.array([p for p, _ in poses]), [r for _, r in poses]


def _speed(pts, every=1):
    return np.linalg.norm(pts[every:] - pts[:-every], axis=1) / (every * DT)


def test_the_two_speeds_are_the_paper_and_iso_figures():
    lim = MotionLimits()
    assert CONTACT_SPEED == lim.speed == lim.limit("contact").speed == 0.05  # paper §7.2
    assert TRANSIT_SPEED == lim.transit_speed == lim.limit("transit").speed == 0.25  # ISO 10218-1 §5.6
    with pytest.raises(ValueError, match="segment kind"):
        lim.limit("fast")


def test_a_transit_line_brakes_into_its_contact_zone(kin):
    """A 20 cm descent whose last 4 cm are contact-critical: the TCP runs at the transit speed, then at the
    contact speed over exactly the zone, and arrives without stopping at the zone's edge."""
    start = Pose(*kin.fk(kin.home))
    goal = Pose(start.pos + np.array([0.0, 0.0, -0.2]), start.rot)
    traj, slow = line_trajectory(kin, kin.home, start, goal, MotionLimits(), DT, "transit", slow_last=0.04)
    pts, _ = _tcp(kin, traj)
    v = _speed(pts)
    to_go = np.linalg.norm(pts - goal.pos, axis=1)
    sure = np.abs(to_go - 0.04) > 1e-3  # the label is the geometry (up to the IK's 1 mm between knots)
    np.testing.assert_array_equal(slow[sure], (to_go <= 0.04)[sure])
    assert v[slow[1:]].max() <= CONTACT_SPEED * 1.02
    assert v[~slow[1:]].max() <= TRANSIT_SPEED * 1.02
    assert v[~slow[1:]].max() >= TRANSIT_SPEED * 0.97
    edge = np.argmax(slow)
    assert v[edge - 1] > 0.9 * CONTACT_SPEED  # no stop between the two speeds
    np.testing.assert_allclose(pts[-1], goal.pos, atol=2e-4)
    assert np.all(np.abs(np.diff(traj, axis=0)) / DT <= kin.velocity * 0.8 + 1e-9)
    # 16 cm at 0.25 m/s and 4 cm at 0.05 m/s, plus the ramps: well under the 4 s the whole line takes slowly
    assert 1.3 < len(traj) * DT < 1.9


def test_lift_off_is_slow_first(kin):
    start = Pose(*kin.fk(kin.home))
    goal = Pose(start.pos + np.array([0.0, 0.0, 0.15]), start.rot)
    traj, slow = line_trajectory(kin, kin.home, start, goal, MotionLimits(), DT, "transit", slow_first=0.03)
    pts, _ = _tcp(kin, traj)
    gone = np.linalg.norm(pts - start.pos, axis=1)
    sure = np.abs(gone - 0.03) > 1e-3
    np.testing.assert_array_equal(slow[sure], (gone <= 0.03)[sure])
    v = _speed(pts)
    assert v[slow[1:]].max() <= CONTACT_SPEED * 1.02
    assert v.max() >= TRANSIT_SPEED * 0.97


def test_a_joint_transit_holds_the_tcp_caps_along_its_curved_path(kin):
    """From the ready pose to a pose 45 cm away and turned 90 deg: the TCP's own path speed and its angular
    speed stay within the transit caps, the joints within 80 % of their limits, and the cap is used."""
    p0, r0 = kin.fk(kin.home)
    rot = r0 @ pin.exp3(np.array([0.0, 0.0, -np.pi / 2]))
    res = solve_ik(kin, p0 + np.array([0.1, 0.35, -0.25]), rot)
    assert res.ok
    lim = MotionLimits()
    traj, low = transit_trajectory(kin, kin.home, res.q, lim, DT)
    pts, rots = _tcp(kin, traj)
    path = np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1))
    assert path > np.linalg.norm(pts[-1] - pts[0]) + 1e-3  # a curve, not a line
    v = _speed(pts)
    w = np.array([np.linalg.norm(pin.log3(a.T @ b)) for a, b in zip(rots, rots[1:])]) / DT
    assert v.max() <= TRANSIT_SPEED * 1.03
    assert w.max() <= lim.limit("transit").angular_speed * 1.03
    assert max(v.max() / TRANSIT_SPEED, w.max() / lim.limit("transit").angular_speed) > 0.95
    assert np.all(np.abs(np.diff(traj, axis=0)) / DT <= kin.velocity * 0.8 + 1e-9)
    np.testing.assert_allclose(traj[-1], res.q)
    assert low == pytest.approx(min(p[2] for p in pts), abs=0.01)
    # the same move as a contact-critical segment takes about five times as long
    slow, _ = transit_trajectory(kin, kin.home, res.q, lim, DT, kind="contact")
    assert 4.0 < len(slow) / len(traj) < 5.5
