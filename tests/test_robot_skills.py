"""Robot skills on the real workcells: MuJoCo physics executing pinocchio-planned trajectories."""

import mujoco
import numpy as np
import pytest

import ergosim.robot as robot_pkg
from ergosim.quat import to_mat
from ergosim.robot import ArmKinematics
from ergosim.robot.panda import PANDA
from ergosim.robot.skills import SkillParams, handover, pick_place
from ergosim.robot.status import SkillStatus
from ergosim.robot.trajectory import CONTACT_SPEED, TRANSIT_SPEED, MotionLimits, Pose, segment_trajectory
from ergosim.scenes import build_scene


@pytest.fixture(scope="module")
def kin():
    return ArmKinematics(PANDA)


@pytest.fixture(scope="module")
def kwear():
    return build_scene("kwear-validation")


@pytest.fixture(scope="module")
def multi():
    return build_scene("multi-subject")


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
    skill = pick_place(wc, "J", pos, quat)
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
    np.testing.assert_allclose(wc.data.qpos[:7], wc.robot_home(), atol=0.01)  # back home
    assert wc.data.ctrl[7] == pytest.approx(0.04)  # gripper open again
    # Timing (the physics since the two-speed robot): four contact-critical zones of ~3.5 cm at 0.05 m/s,
    # the rest a transit at 0.25 m/s; at 0.05 m/s throughout this pick-and-place took 73 s.
    assert 15 < res.duration < 30
    assert sum(t for _, t in res.phases) == pytest.approx(res.duration)
    assert res.phase("contact") >= 4 * skill.zone / 0.05
    assert res.phase("transit") > res.phase("contact") and res.phase("wait") == 0.0


def test_the_gripper_holds_a_part_by_the_weld_without_squeezing_it(kwear, kin):
    """While the robot holds J, no finger touches it (the weld is the grasp) and the fingers stay where they
    closed on it, the part's width apart; the place is still within 5 mm."""
    wc = kwear
    wc.reset()
    m, d = wc.model, wc.data
    fingers = {m.body(f"panda_{s}finger").id for s in ("left", "right")}
    j = m.body("J").id
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "J", pos, quat)
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
            seen["rot"] = to_mat(w.body_pose(profile)[1])
            w.grasp("human_right", profile)
            return True
        return False

    human = wc.human
    still = human.home_deg
    skill = handover(wc, profile, pos, quat, worker_takes)
    while (res := skill.step(wc.data)) is None:  # the twin's loop: mocap writes the worker, then physics
        human.set_angles(wc.data, still)
        mujoco.mj_step(wc.model, wc.data)
    assert res.status is SkillStatus.OK, res.message
    assert seen["error"] < 0.005 and res.place_error < 0.005
    part_rot = seen["rot"]
    angle = np.degrees(np.arccos(np.clip((np.trace(part_rot.T @ to_mat(quat)) - 1) / 2, -1, 1)))
    assert min(angle, 180 - angle) < 3.0  # lying along the handover pose (a profile is symmetric)
    # the worker holds it now; the robot let go and went home
    assert wc.holder_of(profile) == "human_right"
    assert np.linalg.norm(wc.body_pose(profile)[0] - pos) < 0.01
    np.testing.assert_allclose(wc.data.qpos[:7], wc.robot_home(), atol=0.01)
    wc.release("human_right", profile)


def test_unreachable_target_is_a_status(kwear, kin):
    wc = kwear
    wc.reset()
    q0 = wc.data.qpos[:7].copy()
    res = pick_place(wc, "S1", [2.5, 0.0, 1.0], [1, 0, 0, 0]).run_to_completion()
    assert res.status is SkillStatus.UNREACHABLE and not res.ok
    assert "S1" in res.message and "IK" in res.message
    np.testing.assert_allclose(wc.data.qpos[:7], q0, atol=1e-9)  # nothing moved


def test_part_moved_away_gives_not_grasped(kwear, kin):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "S2", pos + [0.0, 0.2, 0.0], quat)
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
    skill = pick_place(wc, "L", pos + [0.0, 0.15, 0.0], quat,
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


def _execute(wc, skill, kin, pose_human: bool = False):
    """Step ``skill`` to completion; per physics step: the commanded TCP (pinocchio FK of the joint targets,
    world frame), the MuJoCo TCP site, and the skill's phase."""
    m, d = wc.model, wc.data
    tcp = m.site("panda_tcp").id
    cmd, act, phase = [], [], []
    still = wc.human.home_deg if pose_human else None
    while (res := skill.step(d)) is None:
        if still is not None:
            wc.human.set_angles(d, still)
        mujoco.mj_step(m, d)
        cmd.append(d.ctrl[:7].copy())
        act.append(d.site_xpos[tcp].copy())
        phase.append(skill.phase)
    base = skill.base
    cmd_tcp = np.array([base.rot @ kin.fk(q)[0] + base.pos for q in cmd])
    return res, cmd_tcp, np.array(act), np.array(phase), float(m.opt.timestep)


def _check_speeds(res, skill, cmd, act, phase, dt):
    """Contact-critical motion at 0.05 m/s, transits (and the way home) at 0.25 m/s: the commanded TCP
    within 2-3 % of the caps, the MuJoCo TCP within its tracking error (a position servo lags ~20 ms, so it
    enters a contact zone still braking: the check is where a touch is possible, within the zone less its
    margin of the points where the gripper closes, opens or waits)."""
    v_cmd = np.linalg.norm(np.diff(cmd, axis=0), axis=1) / dt
    v_act = np.linalg.norm(np.diff(act, axis=0), axis=1) / dt
    ph = phase[1:]
    contact, transit = ph == "contact", np.isin(ph, ["transit", "home"])
    assert contact.sum() * dt >= 4 * skill.zone / CONTACT_SPEED * 0.95
    # linear joint interpolation between IK samples 1 cm apart: up to ~3 % at a sample, by arm configuration
    assert v_cmd[contact].max() <= CONTACT_SPEED * 1.03
    assert v_cmd[transit].max() <= TRANSIT_SPEED * 1.03
    assert v_act[transit].max() <= TRANSIT_SPEED * 1.10
    assert v_act[transit].max() >= TRANSIT_SPEED * 0.9  # the transits do run at the transit speed
    # where the hand stops at a part: the grasp, the place or the handover pose
    stops = [act[i] for i in range(1, len(phase))
             if phase[i] in ("gripper", "wait") and phase[i - 1] == "contact"]
    assert len(stops) == 2
    touch = skill.zone - skill.params.contact_margin
    moving = np.isin(ph, ["contact", "transit", "home"])
    for x in stops:
        near = moving & (np.linalg.norm(act[1:] - x, axis=1) < touch)
        assert near.sum() * dt > 2 * touch / CONTACT_SPEED * 0.9  # in and out
        assert v_act[near].max() <= CONTACT_SPEED * 1.08
    assert sum(t for _, t in res.phases) == pytest.approx(res.duration)
    for name, _ in res.phases:
        assert res.phase(name) == pytest.approx(np.sum(phase == name) * dt, abs=2 * dt)


def test_handover_runs_contact_zones_slow_and_transits_at_the_reduced_speed(multi, kin):
    wc = multi
    wc.reset()
    pos, quat = wc.site_pose("handover")
    t0 = wc.data.time
    taken = {}

    def worker_takes(w):
        if np.linalg.norm(w.body_pose("S1")[0] - pos) < 0.005:
            w.grasp("human_right", "S1")
            taken.setdefault("t", w.data.time - t0)
            return True
        return False

    skill = handover(wc, "S1", pos, quat, worker_takes)
    res, cmd, act, phase, dt = _execute(wc, skill, kin, pose_human=True)
    assert res.status is SkillStatus.OK, res.message
    _check_speeds(res, skill, cmd, act, phase, dt)
    # the zone: fingertips 9.5 mm past the TCP, 15 mm of profile above its grasp, 1 cm of margin
    assert skill.zone == pytest.approx(0.0345, abs=0.002)
    # reach, grasp and carry to the handover pose take about 9 s (39 s at 0.05 m/s throughout)
    assert 6.0 < taken["t"] < 12.0
    wc.release("human_right", "S1")


def test_insertion_runs_its_whole_stroke_at_the_contact_speed(kwear, kin):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose(wc.actions["a2"].target)  # the upper hollow of J
    skill = pick_place(wc, "L", pos, quat, approach=to_mat(quat)[:, 2], seat=True)
    res, cmd, act, phase, dt = _execute(wc, skill, kin)
    assert res.status is SkillStatus.OK, res.message
    _check_speeds(res, skill, cmd, act, phase, dt)
    stroke = skill.params.insert_approach
    # the insertion (in) and the retreat along the hollow's axis (out) at 0.05 m/s, besides the grasp zones
    assert res.phase("contact") >= (2 * stroke + 2 * skill.zone) / CONTACT_SPEED
