"""Robot skills on the real workcells: MuJoCo physics executing pinocchio-planned trajectories."""

import mujoco
import numpy as np
import pytest

import ergosim.robot as robot_pkg
from ergosim.robot import PandaKinematics
from ergosim.robot.skills import SkillParams, handover, pick_place
from ergosim.robot.status import SkillStatus
from ergosim.robot.trajectory import MotionLimits, Pose, segment_trajectory
from ergosim.scenes import build_scene


@pytest.fixture(scope="module")
def kin():
    return PandaKinematics()


@pytest.fixture(scope="module")
def kwear():
    return build_scene("kwear-validation")


@pytest.fixture(scope="module")
def multi():
    return build_scene("multi-subject")


def _mat(quat):
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, np.asarray(quat, dtype=float))
    return m.reshape(3, 3)


def test_public_api_names_exist():
    for name in robot_pkg.__all__:
        assert hasattr(robot_pkg, name), name


def test_line_runs_at_the_paper_speed_within_joint_limits(kin):
    dt = 0.002
    start = Pose(*kin.fk(kin.home))
    goal = Pose(start.pos + np.array([0.1, 0.15, -0.2]), start.rot)
    traj = segment_trajectory(kin, kin.home, start, goal, MotionLimits(), dt)
    tcp = np.array([kin.fk(q)[0] for q in traj[::5]])
    speed = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / (5 * dt)
    assert speed.max() == pytest.approx(0.05, rel=0.02)
    np.testing.assert_allclose(tcp[-1], goal.pos, atol=2e-4)
    assert np.all(np.abs(np.diff(traj, axis=0)) / dt <= kin.velocity + 1e-9)
    # straight: every TCP sample lies on the segment
    d = (goal.pos - start.pos) / np.linalg.norm(goal.pos - start.pos)
    off = (tcp - start.pos) - np.outer((tcp - start.pos) @ d, d)
    assert np.abs(off).max() < 1.5e-3


def test_pick_place_puts_j_in_the_assembly_area(kwear, kin):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "J", pos, quat, kin=kin)
    assert skill.step(wc.data) is None  # steppable: one physics step at a time
    mujoco.mj_step(wc.model, wc.data)
    res = skill.run_to_completion()
    assert res.status is SkillStatus.OK, res.message
    assert res.place_error < 0.005
    j_pos, j_quat = wc.body_pose("J")
    assert np.linalg.norm(j_pos - pos) < 0.005
    assert wc.holder_of("J") is None  # released: it rests on the bench by itself
    mujoco.mj_step(wc.model, wc.data)
    assert abs(wc.data.qvel[wc.model.joint("J").dofadr[0] + 2]) < 0.05
    np.testing.assert_allclose(wc.data.qpos[:7], robot_pkg.HOME_QPOS, atol=0.01)  # back home
    assert wc.data.ctrl[7] == pytest.approx(0.04)  # gripper open again
    assert 20 < res.duration < 200


def test_the_gripper_holds_a_part_by_the_weld_without_squeezing_it(kwear, kin):
    """While the robot holds J, no finger touches it (the weld is the grasp) and the fingers stay where they
    closed on it, the part's width apart; the place is still within 5 mm."""
    wc = kwear
    wc.reset()
    m, d = wc.model, wc.data
    fingers = {m.body(f"panda_{s}finger").id for s in ("left", "right")}
    j = m.body("J").id
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "J", pos, quat, kin=kin)
    held = touching = 0
    opening = []
    while (res := skill.step(d)) is None:
        mujoco.mj_step(m, d)
        if wc.holder_of("J") == "robot":
            held += 1
            opening.append(d.qpos[[m.joint(f"panda_finger_joint{i}").qposadr[0] for i in (1, 2)]].sum())
            touching += sum({m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]} & fingers != set()
                            and j in (m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]) for c in d.contact)
    assert res.status is SkillStatus.OK, res.message
    assert held > 1000 and touching == 0
    width = wc.grip_width("J")
    assert np.ptp(opening) < 3e-4 and abs(np.mean(opening) - width) < 6e-4  # not closing into it
    assert res.place_error < 0.005
    wc.reset()


@pytest.mark.parametrize("profile", ["L", "S1", "S2"])
def test_handover_brings_each_profile_to_the_handover_pose(multi, kin, profile):
    wc = multi
    wc.reset()
    pos, quat = wc.site_pose("handover")
    seen = {}

    def worker_takes(w):  # the worker's right hand closes on the part once it is presented
        err = np.linalg.norm(w.body_pose(profile)[0] - pos)
        if err < 0.005:
            seen["error"] = err
            seen["rot"] = _mat(w.body_pose(profile)[1])
            w.grasp("human_right", profile)
            return True
        return False

    human = wc.human
    still = human.home_deg
    skill = handover(wc, profile, pos, quat, worker_takes, kin=kin)
    while (res := skill.step(wc.data)) is None:  # the twin's loop: mocap writes the worker, then physics
        human.set_angles(wc.data, still)
        mujoco.mj_step(wc.model, wc.data)
    assert res.status is SkillStatus.OK, res.message
    assert seen["error"] < 0.005 and res.place_error < 0.005
    part_rot = seen["rot"]
    angle = np.degrees(np.arccos(np.clip((np.trace(part_rot.T @ _mat(quat)) - 1) / 2, -1, 1)))
    assert min(angle, 180 - angle) < 3.0  # lying along the handover pose (a profile is symmetric)
    # the worker holds it now; the robot let go and went home
    assert wc.holder_of(profile) == "human_right"
    assert np.linalg.norm(wc.body_pose(profile)[0] - pos) < 0.01
    np.testing.assert_allclose(wc.data.qpos[:7], robot_pkg.HOME_QPOS, atol=0.01)
    wc.release("human_right", profile)


def test_unreachable_target_is_a_status(kwear, kin):
    wc = kwear
    wc.reset()
    q0 = wc.data.qpos[:7].copy()
    res = pick_place(wc, "S1", [2.5, 0.0, 1.0], [1, 0, 0, 0], kin=kin).run_to_completion()
    assert res.status is SkillStatus.UNREACHABLE and not res.ok
    assert "S1" in res.message and "IK" in res.message
    np.testing.assert_allclose(wc.data.qpos[:7], q0, atol=1e-9)  # nothing moved


def test_part_moved_away_gives_not_grasped(kwear, kin):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "S2", pos + [0.0, 0.2, 0.0], quat, kin=kin)
    skill.step(wc.data)  # planned against where S2 lies now
    qa = wc.model.joint("S2").qposadr[0]
    wc.data.qpos[qa:qa + 2] += [0.12, 0.0]  # someone moves it before the gripper arrives
    mujoco.mj_forward(wc.model, wc.data)
    res = skill.run_to_completion()
    assert res.status is SkillStatus.NOT_GRASPED, res.message
    assert wc.holder_of("S2") is None


def test_part_knocked_out_of_the_gripper_gives_dropped(kwear, kin):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "L", pos + [0.0, 0.15, 0.0], quat, kin=kin,
                       params=SkillParams(drop_check_every=5))
    m, d = wc.model, wc.data
    res = None
    for _ in range(200_000):
        res = skill.step(d)
        if res is not None:
            break
        mujoco.mj_step(m, d)
        if wc.holder_of("L") == "robot" and d.site_xpos[m.site("panda_tcp").id][2] > 1.1:
            wc.release("robot", "L")  # a collision tears it out of the fingers while carried
            qa = m.joint("L").qposadr[0]
            d.qpos[qa:qa + 3] = [0.45, 0.3, 0.93]
            mujoco.mj_forward(m, d)
    assert res is not None and res.status is SkillStatus.DROPPED, res
    assert "L" in res.message
