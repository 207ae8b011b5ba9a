"""Speed and separation monitoring: ISO/TS 15066 eq. 1 and the speed limit it gives, against hand worked
numbers; the capsule separation against a brute force; the monitor slowing a robot near the worker."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from ergosim.errors import ConfigError
from ergosim.robot.skills import Handover
from ergosim.robot.ssm import SSMParams, allowed_speed, protective_distance, speed_scale
from ergosim.scenes import build_scene
from ergosim.scenes.separation import SeparationModel, capsules_of, segment_distances
from ergosim.twin.robot_track import RobotTrack
from ergosim.twin.ssm_monitor import SafetyMonitor

P = SSMParams()


def test_protective_distance_is_iso_ts_15066_eq_1():
    # S_p = v_h (T_r + T_s) + v_r T_r + v_r T_s / 2 + C + Z_d + Z_r, with T_r 0.1, T_s 0.3, C+Z = 0.08
    assert protective_distance(P, 0.0, 0.0) == pytest.approx(0.08)
    assert protective_distance(P, 1.6, 0.0) == pytest.approx(1.6 * 0.4 + 0.08)
    assert protective_distance(P, 1.0, 0.25) == pytest.approx(0.4 + 0.25 * 0.1 + 0.25 * 0.15 + 0.08)


def test_allowed_speed_inverts_the_protective_distance():
    for v_h in (0.0, 0.3, 1.2):
        for s in (0.1, 0.3, 0.8):
            v = allowed_speed(P, s, v_h)
            if v > 0:
                assert protective_distance(P, v_h, v) == pytest.approx(s)
    assert allowed_speed(P, 0.05, 0.0) == 0.0  # below S_p(0): a protective stop
    assert speed_scale(P, 2.0, 0.0, 0.25) == 1.0
    assert 0 < speed_scale(P, 0.12, 0.0, 0.25) < 1
    assert speed_scale(P, 0.05, 0.0, 0.25) == 0.0
    assert speed_scale(P, 0.05, 0.0, 0.0) == 1.0  # nothing to scale when the robot stands still


def test_enabled_by_execution():
    assert SSMParams().enabled("parallel") and not SSMParams().enabled("sequential")
    assert SSMParams(ssm="on").enabled("sequential") and not SSMParams(ssm="off").enabled("parallel")
    with pytest.raises(ConfigError, match="stopping_time must be >= 0"):
        SSMParams(stopping_time=-1).validate("here")


def test_segment_distances_match_a_brute_force():
    rng = np.random.default_rng(3)
    u = np.linspace(0, 1, 301)
    for k in range(200):
        p0, p1, q0, q1 = (rng.normal(size=(1, 3)) for _ in range(4))
        if k % 4 == 0:
            q1 = q0.copy()  # a point
        if k % 5 == 0:
            q1 = q0 + 0.5 * (p1 - p0)  # parallel
        d, s, t = segment_distances(p0, p1, q0, q1)
        a, b = p0 + (p1 - p0) * u[:, None], q0 + (q1 - q0) * u[:, None]
        brute = np.min(np.linalg.norm(a[:, None] - b[None], axis=2))
        assert brute - 1e-2 <= d[0] <= brute + 1e-9
        gap = (p0 + (p1 - p0) * s[0]) - (q0 + (q1 - q0) * t[0])
        assert np.linalg.norm(gap) == pytest.approx(d[0])


@pytest.fixture(scope="module")
def cell():
    return build_scene("multi-subject")


def test_a_links_capsule_contains_its_mesh(cell):
    m, d = cell.model, cell.data
    mujoco.mj_forward(m, d)
    sep = SeparationModel(m, {"robot": cell.robot().base}, [])
    caps = sep.robots["robot"]
    ends = caps.segments(d)
    for i, g in enumerate(caps.geoms.tolist()):
        if m.geom_type[g] != mujoco.mjtGeom.mjGEOM_MESH:
            continue
        mesh = m.geom_dataid[g]
        start, n = m.mesh_vertadr[mesh], m.mesh_vertnum[mesh]
        verts = d.geom_xpos[g] + m.mesh_vert[start:start + n] @ d.geom_xmat[g].reshape(3, 3).T
        dist, _, _ = segment_distances(np.repeat(ends[0][i:i + 1], n, 0), np.repeat(ends[1][i:i + 1], n, 0),
                                       verts, verts)
        assert dist.max() <= caps.radius[i] + 1e-6, m.geom(g).name


def test_capsules_of_a_sphere_and_a_box():
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.1, 0, 0])
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.3, 0.1, 0.05])
    m = spec.compile()
    caps = capsules_of(m, [0, 1])
    assert caps.radius[0] == pytest.approx(0.1) and caps.half[0] == 0
    assert caps.axis[1] == 0 and caps.half[1] == pytest.approx(0.3)
    assert caps.radius[1] == pytest.approx(np.hypot(0.1, 0.05))


def test_the_monitor_slows_a_robot_that_comes_close(cell):
    track = RobotTrack(cell)
    monitor = SafetyMonitor(cell, {"robot": track}, SSMParams(ssm="on"), scale=True, every=1,
                            dt_control=1 / 60)

    class _Plant:
        data, time, ticks = cell.data, 0.0, 0

    # moving at home, far from the worker: full speed
    track.skill = type("S", (), {"phase": "transit"})()
    mujoco.mj_forward(cell.model, cell.data)
    far = monitor.measure(_Plant)
    assert far > 0.2 and track.speed == 1.0
    # the worker's left hand at the gripper: a protective stop
    tcp = cell.data.site_xpos[cell.robot().tcp].copy()
    hand = cell.model.body("human_left_hand").mocapid[0]
    cell.data.mocap_pos[hand] = tcp
    mujoco.mj_forward(cell.model, cell.data)
    near = monitor.measure(_Plant)
    assert near < 0.08 and track.speed == 0.0
    assert monitor.stopped["robot"] > 0
    rec = monitor.record(_Plant)
    assert rec.min_separation == pytest.approx(min(far, near)) and track.speed == 1.0


def test_a_robot_on_a_handover_creeps_instead_of_stopping(cell):
    """On a hand-over (to the part, with it, the retreat and home), a robot the separation would stop goes
    on at the contact speed: 0.05 m/s, a factor of 0.2 of the 0.25 m/s transit, and its contact-speed
    phases, with the part or without, are not slowed (power and force limiting). A hand-over presented
    where the worker needs it is near the worker, and an idle worker there held the robot still for good
    (the parallel multi-subject runs hung, on the way in, out and on the retreat). A place or an
    insertion is still stopped."""

    class _Plant:
        data, time, ticks = cell.data, 0.0, 0

    def handover(name):
        return object.__new__(type("H", (Handover,), {"phase": name}))

    track = RobotTrack(cell)
    monitor = SafetyMonitor(cell, {"robot": track}, SSMParams(ssm="on"), scale=True, every=1,
                            dt_control=1 / 60)
    mujoco.mj_forward(cell.model, cell.data)
    hand = cell.model.body("human_left_hand").mocapid[0]
    cell.data.mocap_pos[hand] = cell.data.site_xpos[cell.robot().tcp]
    mujoco.mj_forward(cell.model, cell.data)
    part = capsules_of(cell.model, cell.collision_geoms("L").tolist())
    limits = track.params.limits
    creep = limits.speed / limits.transit_speed
    assert creep == pytest.approx(0.2)
    cases = (("transit", part, creep), ("transit", None, creep), ("home", None, creep),
             ("contact", part, 1.0), ("contact", None, 1.0))
    for name, held, expected in cases:
        track.skill = handover(name)
        monitor._held = lambda robot, held=held: held
        assert monitor.measure(_Plant) < 0.08
        assert track.speed == pytest.approx(expected), (name, held is not None)
    assert monitor.stopped["robot"] == 0 and monitor.slowed["robot"] > 0
    monitor._held = lambda robot: None
    for name in ("transit", "contact", "home"):  # a place or an insertion: stopped
        track.skill = type("S", (), {"phase": name})()
        assert monitor.measure(_Plant) < 0.08 and track.speed == 0.0
    assert monitor.stopped["robot"] > 0


def test_planned_time_is_the_skills_time():
    """The robot's expected duration (the time cost) is its planned trajectory: executed, the skill takes
    that long (the gripper's closing stops where the fingers touch, so a little less)."""
    cell = build_scene("gearbox")
    track = RobotTrack(cell)
    geom = cell.actions["g2"]
    planned = track.planned_time(geom)
    result = track.skill_for(geom).run_to_completion()
    assert result.ok
    assert planned == pytest.approx(result.duration, rel=0.05)
