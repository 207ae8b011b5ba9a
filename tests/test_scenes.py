"""Workcells: registry, cell files and overrides, parts, welds (hold, release, seat), reset."""

import dataclasses

import mujoco
import numpy as np
import pytest

import ergosim.scenes as scenes_pkg
from ergosim.errors import ConfigError
from ergosim.scenes import build_scene, default_config, load_cell, scene_names

PROFILES = ("L", "S1", "S2")
ALUMINIUM_DENSITY = 2700.0


@pytest.fixture(scope="module")
def kwear():
    return build_scene("kwear-validation")


@pytest.fixture(scope="module")
def multi():
    return build_scene("multi-subject")


def test_public_api_names_exist():
    for name in scenes_pkg.__all__:
        assert hasattr(scenes_pkg, name), name


def test_registry_lists_scenes_and_rejects_unknown():
    assert {"gearbox", "kwear-validation", "multi-subject"} <= set(scene_names())
    with pytest.raises(ConfigError, match="kwear-validation"):
        build_scene("assembly-line")
    assert default_config("multi_subject") == default_config("multi-subject")


def shelf(cfg):
    return next(f for f in cfg.furniture if f.name == "shelf")


def test_overrides_by_alias_and_dotted_path_and_errors():
    cfg = load_cell("kwear-validation")
    new = load_cell("kwear-validation", shelf_height="1.6", j_xy="0.15,-0.75")
    assert shelf(new).height == 1.6 and new.part("J").xy == (0.15, -0.75)
    assert shelf(cfg).height == 1.45  # frozen original untouched
    assert load_cell("kwear-validation", **{"furniture.shelf.height": "1.6"}).furniture == new.furniture
    with pytest.raises(ConfigError, match="unknown key 'shelf_hieght'"):
        load_cell("kwear-validation", shelf_hieght=1.9)
    with pytest.raises(ConfigError, match="shelf_height='high' is not a number"):
        load_cell("kwear-validation", shelf_height="high")
    with pytest.raises(ConfigError, match="stature"):
        load_cell("kwear-validation", stature=3.0)
    with pytest.raises(ConfigError, match="not on the shelf_top"):
        load_cell("kwear-validation", j_xy=(0.5, 0.0))
    with pytest.raises(ConfigError, match="l_xy='1' has 1 value, expected 2"):
        load_cell("kwear-validation", l_xy="1")
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.name = "other"


def test_layout_change_moves_geometry(kwear):
    high = build_scene("kwear-validation", shelf_height=1.6)
    assert high.body_pose("J")[0][2] - kwear.body_pose("J")[0][2] == pytest.approx(0.15)
    assert high.model.geom("shelf_top").pos[2] - kwear.model.geom("shelf_top").pos[2] == pytest.approx(0.15)


def test_parts_are_aluminium(kwear):
    m, cfg = kwear.model, kwear.config
    for p in PROFILES:
        length = cfg.part(p).size[0]
        assert m.body(p).mass[0] == pytest.approx(ALUMINIUM_DENSITY * cfg.part(p).section_area * length)
        assert m.geom(f"{p}_geom").size[0] * 2 == pytest.approx(length)
    assert m.geom("S1_geom").size[0] == m.geom("S2_geom").size[0] > m.geom("L_geom").size[0]
    # J: a few hundred grams of aluminium, walls only (hollows are empty)
    assert 0.15 < m.body("J").mass[0] < 0.4
    for p in PROFILES:
        assert m.site(f"J_hollow_{p}").id >= 0
        assert m.jnt_type[m.joint(p).id] == mujoco.mjtJoint.mjJNT_FREE


def test_initial_layout_matches_the_paper(kwear, multi):
    # KWear: J on the top ledge of the shelf at the worker's right; the assembly goes to a lower ledge
    j, _ = kwear.body_pose("J")
    assert j[1] < -0.3 and j[2] > shelf(kwear.config).height
    assert kwear.site_pose("shelf_target")[0][2] < shelf(kwear.config).height
    # multi-subject: pieces and robot on the worker's left (+y), J and L with the robot on the side table,
    # S1 and S2 close on the bench; the assembly area and the monitor in front
    for p in ("J", "L", "S1", "S2", "panda_link0"):
        assert multi.body_pose(p)[0][1] > 0.05
    for p in ("J", "L", "panda_link0"):
        assert multi.body_pose(p)[0][1] > 0.5
    assert abs(multi.site_pose("assembly_area")[0][1]) < 0.2
    assert multi.model.geom("monitor").pos[0] > multi.site_pose("assembly_area")[0][0]
    far = max(PROFILES + ("J",), key=lambda p: np.linalg.norm(multi.body_pose(p)[0][:2]))
    assert far == "L"


def test_actions_geometry(kwear, multi):
    for wc in (kwear, multi):
        assert list(wc.actions) == ["a1", "a2", "a3", "a4", "a5"]
        for g in wc.actions.values():
            assert wc.model.site(g.target).id >= 0
            assert wc.model.body(g.part).id >= 0
    assert multi.actions["a2"].handover == "a2_present" and kwear.actions["a2"].handover is None
    assert multi.actions["a5"].kind == "remove"


def test_human_is_mocap_segments_driven_by_the_canonical_joints(multi):
    """The scene's human adds no degrees of freedom: one mocap body per segment of the articulated model,
    which has the 22 canonical joints; posing it moves the scene's segments exactly."""
    human = multi.human
    assert len(human.kin.qadr) == 22
    assert multi.model.nmocap == human.kin_model.nbody - 1
    assert not any(multi.model.body(n).name.startswith("human") for n in multi.model.jnt_bodyid)
    assert set(multi.holders) == {"robot", "human_right", "human_left"}
    angles = human.home_deg.copy()
    angles[human.index["shoulder_flexion"]] = 80.0
    angles[human.index["trunk_rotation"]] = -15.0
    human.set_angles(multi.data, angles)
    kd = mujoco.MjData(human.kin_model)
    human.kin.set_angles(kd, angles)
    for b in range(1, human.kin_model.nbody):
        name = human.kin_model.body(b).name
        np.testing.assert_allclose(multi.data.xpos[multi.model.body(name).id], kd.xpos[b], atol=1e-12)
        np.testing.assert_allclose(multi.data.xquat[multi.model.body(name).id], kd.xquat[b], atol=1e-12)
    np.testing.assert_allclose(human.hand_pos(multi.data), kd.site_xpos[human.kin.hand_site["right"]],
                               atol=1e-12)
    multi.reset()


def _step(wc, seconds):
    for _ in range(int(seconds / wc.model.opt.timestep)):
        mujoco.mj_step(wc.model, wc.data)


def test_hold_moves_with_hand_and_release_falls(kwear):
    wc = kwear
    wc.reset()
    m, d = wc.model, wc.data
    human = wc.human
    # put S1 into the left hand (as if picked up), then hold it there
    qa = m.joint("S1").qposadr[0]
    d.qpos[qa:qa + 3] = human.hand_pos(d, "left")
    mujoco.mj_forward(m, d)
    wc.grasp("human_left", "S1")
    assert wc.holder_of("S1") == "human_left" and wc.is_held("human_left", "S1")
    _step(wc, 0.05)
    assert np.linalg.norm(wc.body_pose("S1")[0] - human.hand_pos(d, "left")) < 2e-3  # no jump
    h0 = human.hand_pos(d, "left")
    angles = human.home_deg.copy()  # the mocap stream writes every angle each step
    for k in range(1000):  # raise the left arm sideways (clear of the bench); the part goes with the hand
        angles[human.index["left_shoulder_abduction"]] = np.degrees(0.001 * k)
        human.set_angles(d, angles)
        mujoco.mj_step(m, d)
        if k % 100 == 0:  # while moving at 0.5 rad/s the soft weld trails a little
            assert np.linalg.norm(wc.body_pose("S1")[0] - human.hand_pos(d, "left")) < 0.015
    for _ in range(50):  # hold the pose
        human.set_angles(d, angles)
        mujoco.mj_step(m, d)
    assert human.hand_pos(d, "left")[2] > h0[2] + 0.1
    assert np.linalg.norm(wc.body_pose("S1")[0] - human.hand_pos(d, "left")) < 5e-3
    z_held = wc.body_pose("S1")[0][2]
    wc.release("human_left", "S1")
    _step(wc, 0.2)
    assert wc.body_pose("S1")[0][2] < z_held - 0.1  # falls under gravity
    wc.reset()


def test_seat_within_tolerance_only(kwear):
    wc = kwear
    wc.reset()
    m, d = wc.model, wc.data
    spos, squat = wc.site_pose("J_hollow_S1")
    qa = m.joint("S1").qposadr[0]
    d.qpos[qa:qa + 3] = spos + [0.02, 0, 0]
    d.qpos[qa + 3:qa + 7] = squat
    mujoco.mj_forward(m, d)
    res = wc.seat("S1")
    assert not res.seated and res.pos_error == pytest.approx(0.02, abs=1e-6)
    d.qpos[qa:qa + 3] = spos + [0.003, -0.002, 0.001]
    mujoco.mj_forward(m, d)
    res = wc.seat("S1")
    assert res.seated and wc.is_seated("S1")
    _step(wc, 0.5)
    dist, angle = wc.seat_error("S1")
    assert dist < 5e-4 and angle < 0.5  # pulled into the exact seated pose
    assert wc.grasp_site("J") == "S1_grasp_end"  # the assembly is now taken by its upright profile
    with pytest.raises(ConfigError):
        wc.seat("J")
    wc.reset_parts()
    assert not wc.is_seated("S1")
    np.testing.assert_allclose(wc.body_pose("S1")[0], m.key_qpos[wc.home_key][qa:qa + 3])
    wc.reset()


def _collides(m, g1: int, g2: int) -> bool:
    return bool(m.geom_contype[g1] & m.geom_conaffinity[g2] or m.geom_contype[g2] & m.geom_conaffinity[g1])


def test_a_part_the_robot_holds_stops_colliding_with_the_robot_only(kwear):
    """The weld is the grasp: fingers on a held part would only add contacts fighting it. The held assembly
    still collides with the furniture; the other parts still collide with the fingers; release restores it,
    and leaves a part the worker carries (passing through everything) as it is."""
    wc = kwear
    wc.reset()
    m = wc.model
    finger = next(g for g in range(m.ngeom) if m.geom_bodyid[g] == m.body("panda_leftfinger").id
                  and m.geom_contype[g])
    bench = m.geom("bench").id

    ids = {p: [g for g in range(m.ngeom) if m.geom_bodyid[g] == m.body(p).id and m.geom_contype[g]]
           for p in ("J", "S1", "L")}

    def geoms(part):
        return ids[part]

    spos, squat = wc.site_pose("J_hollow_S1")
    qa = m.joint("S1").qposadr[0]
    wc.data.qpos[qa:qa + 3], wc.data.qpos[qa + 3:qa + 7] = spos, squat
    mujoco.mj_forward(m, wc.data)
    assert wc.seat("S1").seated
    before = {p: [(m.geom_contype[g], m.geom_conaffinity[g]) for g in geoms(p)] for p in ("J", "S1", "L")}
    wc.grasp("robot", "S1")  # the assembly J + S1, taken by its profile
    for p in ("J", "S1"):
        assert not any(_collides(m, g, finger) for g in geoms(p)), p
        assert all(_collides(m, g, bench) for g in geoms(p)), p
    assert all(_collides(m, g, finger) for g in geoms("L"))
    wc.release("robot", "S1")
    assert {p: [(m.geom_contype[g], m.geom_conaffinity[g]) for g in geoms(p)] for p in before} == before
    wc.grasp("robot", "L")
    m.geom_contype[geoms("L")] = 0  # handed over: the worker's carry passes through everything
    m.geom_conaffinity[geoms("L")] = 0
    wc.release("robot", "L")
    assert not m.geom_contype[geoms("L")].any() and not m.geom_conaffinity[geoms("L")].any()
    wc.reset()
    assert {p: [(m.geom_contype[g], m.geom_conaffinity[g]) for g in geoms(p)] for p in before} == before


def test_unknown_holder_or_part(kwear):
    with pytest.raises(ConfigError, match="holders"):
        kwear.grasp("human_foot", "J")
    with pytest.raises(ConfigError, match="parts"):
        kwear.grasp("robot", "K")
