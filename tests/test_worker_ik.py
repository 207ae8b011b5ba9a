"""The whole-body IK: legs that follow the knee, the gaze Jacobian, stance within its area, reach."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from ergosim.human import HumanModel, human_spec
from ergosim.worker import BODY, StandingArea, WholeBodyIK, rest_angles
from ergosim.worker.gaze import gaze_angles, gaze_excess
from ergosim.worker.ik_prior import NECK_NEUTRAL_DEG, TRUNK_NEUTRAL_DEG, default_prior
from ergosim.worker.stance import area_from_footprints

I = {n: i for i, n in enumerate(BODY)}  # noqa: E741 - an index
FREE = StandingArea((-0.3, 0.15), (-0.35, 0.35), (-90.0, 90.0))


@pytest.fixture(scope="module")
def ik():
    return WholeBodyIK(human_spec(1.75).compile())


@pytest.fixture(scope="module")
def rest():
    return np.concatenate([rest_angles(), np.zeros(4)])


def test_bent_knees_lower_the_pelvis_and_keep_both_feet_flat_where_they_stand():
    model = human_spec(1.75).compile()
    data = mujoco.MjData(model)
    human = HumanModel(model)
    feet = ("human_right_foot", "human_left_foot")
    human.set_body(data, np.zeros(22), np.zeros(4))
    standing = {f: (data.xpos[model.body(f).id].copy(), data.xmat[model.body(f).id].copy()) for f in feet}
    pelvis0 = data.xpos[model.body("human_pelvis").id].copy()
    human.set_body(data, np.zeros(22), np.array([0.0, 0.0, 0.0, 80.0]))
    drop = pelvis0[2] - data.xpos[model.body("human_pelvis").id][2]
    assert drop == pytest.approx(human.legs.length * (1 - math.cos(math.radians(40.0))), abs=1e-9)
    for f in feet:
        pos, mat = data.xpos[model.body(f).id], data.xmat[model.body(f).id]
        assert np.linalg.norm(pos - standing[f][0]) < 0.002  # thigh and shank differ by 0.001 H
        np.testing.assert_allclose(mat, standing[f][1], atol=1e-9)  # flat
    assert human.legs.knee_of(human.legs.drop(1.0)) == pytest.approx(1.0)


def test_a_step_and_a_turn_move_the_whole_body_about_the_spot():
    model = human_spec(1.75).compile()
    data = mujoco.MjData(model)
    human = HumanModel(model)
    human.set_body(data, np.zeros(22), np.array([0.2, -0.1, 90.0, 0.0]))
    pelvis = data.xpos[model.body("human_pelvis").id]
    np.testing.assert_allclose(pelvis[:2], [0.2, -0.1], atol=1e-12)
    assert data.xmat[model.body("human_torso").id].reshape(3, 3)[:, 0] == pytest.approx([0, 1, 0], abs=1e-9)


def test_the_gaze_jacobian_matches_finite_differences(ik, rest):
    model, data = ik.model, ik.data
    q = ik.to_solver(rest + 0.1)
    site = ik.human.eye_site
    point = np.array([0.5, -0.4, 0.9])
    act = ik.active["right"]
    dof = ik.dofadr[act]
    jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))

    def excess(qq):
        ik._fk(qq)
        mujoco.mj_comPos(model, data)
        mujoco.mj_jacSite(model, data, jp, jr, site)
        mat = data.site_xmat[site].reshape(3, 3).copy()
        return gaze_excess(point, data.site_xpos[site].copy(), mat, jp[:, dof].copy(), jr[:, dof].copy(),
                           0.0, 0.0, 0.0)

    e0, jac = excess(q)
    for k, a in enumerate(ik.qadr[act]):
        dq = q.copy()
        dq[list(ik.qadr).index(a)] += 1e-6
        np.testing.assert_allclose((excess(dq)[0] - e0) / 1e-6, jac[:, k], atol=1e-4)
    assert gaze_angles(np.array([1.0, 1.0, -math.sqrt(2.0)])) == pytest.approx((math.pi / 4, math.pi / 4))


@pytest.mark.parametrize("target", [(0.45, 0.0, 0.95), (0.2, 0.62, 0.88), (0.18, -0.74, 1.5), (0.5, 0.0, 0.5),
                                    (-0.27, -0.76, 1.6)])
def test_every_target_is_reached_planted_or_free_and_a_free_stance_stays_in_its_area(ik, rest, target):
    for area in (StandingArea.planted(), FREE):
        sol = ik.solve(rest, np.array(target), area=area)
        assert sol.pos_error < 0.02, (area, sol.pos_error)
        assert area.contains(sol.stance) if not area.is_planted else not sol.stance[:3].any()
        assert np.linalg.norm(ik.hand_pos(sol.body) - target) == pytest.approx(sol.pos_error, abs=1e-9)


def test_the_head_looks_at_the_target_within_what_the_eyes_take(ik, rest):
    sol = ik.solve(rest, np.array([0.4, -0.3, 0.9]), area=StandingArea.planted())
    ik._fk(ik.to_solver(sol.body))
    site = ik.human.eye_site
    v = ik.data.site_xmat[site].reshape(3, 3).T @ (np.array([0.4, -0.3, 0.9]) - ik.data.site_xpos[site])
    yaw, pitch = np.degrees(gaze_angles(v))
    pr = ik.prior
    assert abs(yaw) <= pr.eye_side_deg + 2.0 and -pr.eye_up_deg - 2.0 <= pitch <= pr.eye_down_deg + 2.0


def test_low_targets_bend_the_knees_far_ones_lean_the_trunk(ik, rest):
    low = ik.solve(rest, np.array([0.4, 0.0, 0.3]), area=StandingArea.planted())
    assert low.stance[3] > 30.0
    high = ik.solve(rest, np.array([0.4, 0.0, 1.2]), area=StandingArea.planted())
    assert high.stance[3] < 1.0  # straight legs cost nothing to keep: the knee prior's slope is finite


def test_priors_are_the_iso_11226_neutral_zones():
    pr = default_prior(trunk_use=1.0)
    for name, sigma in {**TRUNK_NEUTRAL_DEG, **NECK_NEUTRAL_DEG}.items():
        assert pr.sigma[I[name]] == sigma
    assert default_prior(trunk_use=1.5).sigma[I["trunk_flexion"]] == 30.0
    # extension of trunk and neck is outside their neutral zones: the comfort box starts at 0
    assert pr.comfort_lo[I["trunk_flexion"]] == pr.comfort_lo[I["neck_flexion"]] == 0.0


def test_the_default_standing_area_stops_the_body_short_of_the_furniture():
    """A 1.75 m worker 0.30 m from a bench in front, a side table 0.55 m to the left: one step (0.359 m)
    either way, cut to 0.30 - 0.149 m in front; the side table is beyond a step."""
    bench = (np.array([0.62, 0.0]), np.array([0.32, 0.5]))
    side = (np.array([0.36, 0.80]), np.array([0.38, 0.25]))
    area = area_from_footprints([bench, side], 1.75)
    assert area.x == pytest.approx((-0.35875, 0.30 - 0.085 * 1.75))
    assert area.y == pytest.approx((-0.35875, 0.35875))
    assert area.turn == (-90.0, 90.0)
    shelf_right = (np.array([0.03, -0.62]), np.array([0.25, 0.25]))
    assert area_from_footprints([shelf_right], 1.75).y[0] == pytest.approx(-0.37 + 0.085 * 1.75)
