"""The whole-body IK: legs over flat feet, the gaze and leg Jacobians, balance, the stance chosen first,
furniture as hard limits, reach."""

from __future__ import annotations

import math

import mink
import mujoco
import numpy as np
import pytest

from ergosim.human import HumanModel, human_spec
from ergosim.human.legs import DRIVEN
from ergosim.worker import BODY, StandingArea, WholeBodyIK, rest_angles
from ergosim.worker.balance import BALANCE_MARGIN
from ergosim.worker.gaze import gaze_angles
from ergosim.worker.ik_prior import (
    NECK_COMFORT_DEG,
    NECK_NEUTRAL_DEG,
    STOOP_KNEE_DEG,
    TRUNK_NEUTRAL_DEG,
    default_prior,
    squat_prior,
)
from ergosim.worker.ik_tasks import GazeTask, LegCoupling
from ergosim.worker.obstacles import ik_model
from ergosim.worker.stance import StanceRule, area_from_footprints, choose_stance

I = {n: i for i, n in enumerate(BODY)}  # noqa: E741 - an index
N = 22


@pytest.fixture(scope="module")
def ik():
    return WholeBodyIK(human_spec(1.75).compile())


@pytest.fixture(scope="module")
def rest():
    return np.concatenate([rest_angles(), np.zeros(5)])


def _feet(model, data):
    return {f: (data.xpos[model.body(f).id].copy(), data.xmat[model.body(f).id].copy())
            for f in ("human_right_foot", "human_left_foot")}


def test_the_legs_move_the_hips_over_flat_feet_that_stay_where_they_stand():
    model = human_spec(1.75).compile()
    data = mujoco.MjData(model)
    human = HumanModel(model)
    legs = human.legs
    human.set_body(data, np.zeros(N), np.zeros(5))
    standing = _feet(model, data)
    pelvis0 = data.xpos[model.body("human_pelvis").id].copy()
    for knee, ankle in ((80.0, 40.0), (20.0, -12.0), (100.0, 20.0)):
        human.set_body(data, np.zeros(N), np.array([0.0, 0.0, 0.0, knee, ankle]))
        pelvis = data.xpos[model.body("human_pelvis").id]
        shift, drop = legs.hip(math.radians(knee), math.radians(ankle))
        np.testing.assert_allclose(pelvis - pelvis0, [shift, 0.0, -drop], atol=1e-9)
        for f, (pos, mat) in _feet(model, data).items():
            np.testing.assert_allclose(pos, standing[f][0], atol=1e-9)
            np.testing.assert_allclose(mat, standing[f][1], atol=1e-9)  # flat
        # the pelvis stays upright: the hip flexes by the knee angle less the shank's lean
        np.testing.assert_allclose(data.xmat[model.body("human_pelvis").id], np.eye(3).reshape(9), atol=1e-9)
    # a squat with the shanks at half the knee keeps the hip over the ankle (thigh and shank differ 0.001 H)
    assert abs(legs.hip(math.radians(80.0), math.radians(40.0))[0]) < 0.002
    # a stoop, the shanks leaning back, moves the hips back behind the feet
    assert legs.hip(math.radians(10.0), math.radians(-10.0))[0] < -0.1


def test_a_step_and_a_turn_move_the_whole_body_about_the_spot():
    model = human_spec(1.75).compile()
    data = mujoco.MjData(model)
    human = HumanModel(model)
    human.set_body(data, np.zeros(N), np.array([0.2, -0.1, 90.0, 0.0, 0.0]))
    pelvis = data.xpos[model.body("human_pelvis").id]
    np.testing.assert_allclose(pelvis[:2], [0.2, -0.1], atol=1e-12)
    assert data.xmat[model.body("human_torso").id].reshape(3, 3)[:, 0] == pytest.approx([0, 1, 0], abs=1e-9)


def _finite_difference(config, task, q, eps=1e-6):
    model = config.model
    config.update(q)
    e0 = task.compute_error(config).copy()
    jac = task.compute_jacobian(config).copy()
    num = np.zeros_like(jac)
    for k in range(model.nv):
        dq = np.zeros(model.nv)
        dq[k] = eps
        q1 = q.copy()
        mujoco.mj_integratePos(model, q1, dq, 1.0)
        config.update(q1)
        num[:, k] = (task.compute_error(config) - e0) / eps
    config.update(q)
    return jac, num


def test_the_gaze_jacobian_matches_finite_differences(ik, rest):
    config = mink.Configuration(ik.model)
    gaze = GazeTask(ik.model, ik.human.eye_site, 0.2, 0.0, 0.0, 0.0)
    gaze.look_at(np.array([0.5, -0.4, 0.9]))
    jac, num = _finite_difference(config, gaze, ik.qpos(rest + 0.1))
    np.testing.assert_allclose(num, jac, atol=1e-4)
    assert gaze_angles(np.array([1.0, 1.0, -math.sqrt(2.0)])) == pytest.approx((math.pi / 4, math.pi / 4))


def test_the_leg_coupling_jacobian_matches_finite_differences(ik, rest):
    config = mink.Configuration(ik.model)
    legs = LegCoupling(ik.model, ik.human.legs)
    body = rest.copy()
    body[I["knee_flexion"]], body[I["ankle_dorsiflexion"]] = 50.0, 10.0
    q = ik.qpos(body)
    config.update(q)
    assert np.abs(legs.compute_error(config)).max() < 1e-12  # written consistent
    jac, num = _finite_difference(config, legs, q)
    driven = [ik.model.jnt_dofadr[ik.model.joint(n).id] for n in DRIVEN]
    knee_ankle = [ik.model.jnt_dofadr[ik.model.joint(n).id] for n in ("knee_flexion", "ankle_dorsiflexion")]
    # moving a driven joint alone breaks the coupling one for one; the knee and the ankle move them all
    np.testing.assert_allclose(num[:, driven], jac[:, driven], atol=1e-6)
    np.testing.assert_allclose(num[:, knee_ankle], jac[:, knee_ankle], atol=1e-5)


@pytest.mark.parametrize("target", [(0.45, 0.0, 0.95), (0.2, 0.55, 0.88), (0.18, -0.6, 1.5), (0.5, 0.0, 0.5),
                                    (0.3, -0.3, 1.6)])
def test_every_target_is_reached_in_balance_with_the_feet_where_the_stance_put_them(ik, rest, target):
    start = rest.copy()
    start[N:N + 3] = [0.05, -0.02, 10.0]
    sol = ik.solve(start, np.array(target))
    assert sol.pos_error < 0.01, sol.pos_error
    np.testing.assert_array_equal(sol.stance[:3], start[N:N + 3])  # the stance is not the solver's to move
    assert np.linalg.norm(ik.hand_pos(sol.body) - target) == pytest.approx(sol.pos_error, abs=1e-9)
    assert ik.balance_path(sol.body[None])[0] >= BALANCE_MARGIN - 1e-3


def test_the_eyes_take_the_gaze_first_and_the_neck_stays_off_its_limit(ik, rest):
    target = np.array([0.4, -0.3, 0.9])
    sol = ik.solve(rest, target)
    ik._fk(ik.qpos(sol.body))
    site = ik.human.eye_site
    v = ik.data.site_xmat[site].reshape(3, 3).T @ (target - ik.data.site_xpos[site])
    yaw, pitch = np.degrees(gaze_angles(v))
    pr = ik.prior
    # the eyes look down at least their preferred declination before the neck takes more
    assert pitch >= pr.eye_down_deg - 1.0 and abs(yaw) <= pr.eye_side_deg + 5.0
    low = ik.solve(rest, np.array([0.3, -0.2, 0.75]))
    assert low.angles[I["neck_flexion"]] < NECK_COMFORT_DEG + 3.0 < 45.0 - 3.0


def test_below_the_knee_the_worker_squats_above_it_the_legs_stay_straight(ik, rest):
    squat = squat_prior(ik.prior)
    start = rest.copy()
    start[I["knee_flexion"]], start[I["ankle_dorsiflexion"]] = squat.pref[I["knee_flexion"]], 30.0
    low = ik.solve(start, np.array([0.4, -0.15, 0.3]), prior=squat)
    assert low.stance[3] > 30.0 and low.pos_error < 0.01
    high = ik.solve(rest, np.array([0.4, 0.0, 1.2]))
    assert high.stance[3] < STOOP_KNEE_DEG


def test_a_stoop_shifts_the_hips_back_to_keep_the_centre_of_mass_over_the_feet(ik, rest):
    sol = ik.solve(rest, np.array([0.6, -0.2, 0.55]))
    shift, _ = ik.human.legs.hip(*np.radians(sol.stance[3:5]))
    assert sol.angles[I["trunk_flexion"]] > 30.0 and shift < -0.02
    assert ik.balance_path(sol.body[None])[0] >= BALANCE_MARGIN - 1e-3


def test_the_furniture_is_a_hard_limit_and_a_posture_inside_it_is_pushed_out(rest):
    # a bench whose near edge is 0.30 m in front of the worker, top at 0.9 m
    built = ik_model(human_spec(1.75), [(np.array([0.62, 0.0, 0.88]), np.array([0.32, 0.5, 0.02]), 0.0)])
    ik = WholeBodyIK(built.model, segments=built.segments, obstacles=built.obstacles, forearms=built.forearms)
    for target in ([0.5, -0.2, 0.93], [0.45, 0.0, 0.95], [0.6, -0.25, 0.92]):
        ik.solve(rest, np.array(target))
        assert ik.clearance() >= -1e-3
    # a forearm held through the bench top: pushed out while the hand keeps to its point
    inside = rest.copy()
    inside[I["trunk_flexion"]], inside[I["shoulder_flexion"]], inside[I["elbow_flexion"]] = 20.0, 40.0, 10.0
    ik._fk(ik.qpos(inside))
    assert ik.clearance() < 0.0
    hand = ik.hand_pos(inside)
    out = ik.solve(inside, hand + np.array([0.0, 0.0, 0.1]))
    assert ik.clearance() >= -1e-3 and out.pos_error < 0.02


def test_priors_are_the_iso_11226_neutral_zones_and_hill_and_kroemer_for_the_eyes():
    pr = default_prior(trunk_use=1.0)
    for name, sigma in {**TRUNK_NEUTRAL_DEG, **NECK_NEUTRAL_DEG}.items():
        assert pr.sigma[I[name]] == sigma
    assert default_prior(trunk_use=1.5).sigma[I["trunk_flexion"]] == 30.0
    # extension of trunk and neck is outside their neutral zones: the comfort box starts at 0
    assert pr.comfort_lo[I["trunk_flexion"]] == pr.comfort_lo[I["neck_flexion"]] == 0.0
    assert pr.comfort_hi[I["neck_flexion"]] == NECK_COMFORT_DEG
    assert pr.eye_down_deg == 29.0 and pr.gaze_sigma_deg == 12.0


def test_the_default_standing_area_stops_the_body_short_of_the_furniture():
    """A 1.75 m worker 0.30 m from a bench in front, a side table 0.55 m to the left: one step (0.7175 m)
    either way, cut to 0.30 - 0.149 m in front and 0.55 - 0.149 m to the left."""
    bench = (np.array([0.62, 0.0]), np.array([0.32, 0.5]))
    side = (np.array([0.36, 0.80]), np.array([0.38, 0.25]))
    area = area_from_footprints([bench, side], 1.75)
    assert area.x == pytest.approx((-0.7175, 0.30 - 0.085 * 1.75))
    assert area.y == pytest.approx((-0.7175, 0.55 - 0.085 * 1.75))
    assert area.turn == (-90.0, 90.0)
    shelf_right = (np.array([0.03, -0.62]), np.array([0.25, 0.25]))
    assert area_from_footprints([shelf_right], 1.75).y[0] == pytest.approx(-0.37 + 0.085 * 1.75)


RULE = StanceRule(arm_reach=0.675, shoulder_y=-0.2, knee_height=0.5)
AREA = StandingArea((-0.7, 0.15), (-0.7, 0.4), (-90.0, 90.0))


def test_the_stance_faces_far_to_the_side_targets_and_steps_only_towards_what_is_out_of_reach():
    # within reach in front: worked from the spot
    np.testing.assert_array_equal(choose_stance(np.array([0.45, -0.1, 0.9]), RULE, AREA), [0.0, 0.0, 0.0])
    # 71 deg to the left, 0.80 m away (the §7.2 L): faced, and stepped towards until 0.7 of the reach
    stance = choose_stance(np.array([0.26, 0.76, 0.87]), RULE, AREA)
    assert stance[2] == pytest.approx(math.degrees(math.atan2(0.76, 0.26)))
    step = float(np.hypot(*stance[:2]))
    assert step >= 0.25 and stance[1] <= AREA.y[1] + 1e-12
    assert np.dot(stance[:2], [0.26, 0.76]) > 0.0  # towards it, never away
    # a planted area keeps the spot
    np.testing.assert_array_equal(choose_stance(np.array([0.26, 0.76, 0.87]), RULE, StandingArea.planted()),
                                  np.zeros(3))
    # the step stops at the area's edge along its line
    far = choose_stance(np.array([1.5, 0.0, 0.9]), RULE, AREA)
    assert far[0] == pytest.approx(AREA.x[1]) and abs(far[1]) < 0.1
