"""A skill is planned as a timed program, then stepped: planned_time reads the program the executor runs."""

import mujoco
import numpy as np
import pytest

from ergosim.robot.skill_program import Carry, Grasp, Leave, Open, Pause, Wait
from ergosim.robot.skills import SkillParams, handover, pick_place
from ergosim.robot.status import SkillStatus
from ergosim.robot.trajectory import MotionLimits
from ergosim.scenes import build_scene

# the segments whose length the physics decides: the fingers stop where they touch, the carry is re-planned
# from the actual grasp, the way out starts where that carry ended, a hand-over waits for the worker
PHYSICS = (Grasp, Open, Carry, Leave, Wait)


@pytest.fixture(scope="module")
def kwear():
    return build_scene("kwear-validation")


@pytest.fixture(scope="module")
def multi():
    return build_scene("multi-subject")


def _state(wc):
    return wc.data.qpos.copy(), wc.data.ctrl.copy(), wc.model.eq_active0.copy(), wc.data.eq_active.copy()


def _run(wc, skill, still=None):
    attrs = set(vars(skill))
    while (res := skill.step(wc.data)) is None:
        if still is not None:
            wc.human.set_angles(wc.data, still)
        mujoco.mj_step(wc.model, wc.data)
    assert set(vars(skill)) == attrs  # nothing is created mid-run
    return res


def _check_program(skill, res, planned_time):
    program = skill.program
    assert program.planned_time == planned_time  # planned_time is the executed program's own plan
    assert [s for s, _ in skill.executed] == list(program.segments)
    for segment, steps in skill.executed:
        if not isinstance(segment, PHYSICS):
            assert steps == segment.steps, segment  # motions and pauses run exactly as planned
    executed = sum(n for _, n in skill.executed)
    assert executed * skill.dt == pytest.approx(res.duration, abs=1e-9)
    # what the physics changed: a few steps of the gripper, the re-planned carry and its bridge (and the wait)
    waits = sum(n for s, n in skill.executed if isinstance(s, Wait)) * skill.dt
    assert abs(res.duration - waits - planned_time) < 0.1
    return {type(s).__name__: n - s.steps for s, n in skill.executed if isinstance(s, PHYSICS)}


def test_a_pick_and_place_takes_its_planned_time(kwear):
    wc = kwear
    wc.reset()
    pos, quat = wc.site_pose("bench_target")
    skill = pick_place(wc, "J", pos, quat)
    state = _state(wc)
    planned = skill.planned_time()
    for a, b in zip(state, _state(wc), strict=True):  # planning changes nothing
        np.testing.assert_array_equal(a, b)
    assert skill.program is None and skill.zone == skill.params.approach
    res = _run(wc, skill)
    assert res.status is SkillStatus.OK, res.message
    extra = _check_program(skill, res, planned)
    pauses = [s for s in skill.program.segments if isinstance(s, Pause)]
    assert [p.steps * skill.dt for p in pauses] == pytest.approx([0.1, 0.25, 0.25, 0.25, 0.25])
    assert abs(extra["Grasp"]) <= 20 and abs(extra["Open"]) <= 5, extra  # the fingers stop on contact
    wc.reset()


def test_a_hand_over_takes_its_planned_time_besides_the_wait(multi):
    wc = multi
    wc.reset()
    pos, quat = wc.site_pose("handover")
    waited = {}

    def worker_takes(w):
        if np.linalg.norm(w.body_pose("S1")[0] - pos) < 0.005 and w.data.time >= waited.setdefault(
                "until", w.data.time + 0.5):  # the worker takes it half a second after it arrives
            w.grasp("human_right", "S1")
            return True
        return False

    skill = handover(wc, "S1", pos, quat, worker_takes)
    planned = skill.planned_time()
    res = _run(wc, skill, still=wc.human.home_deg)
    assert res.status is SkillStatus.OK, res.message
    wait = next(n for s, n in skill.executed if isinstance(s, Wait)) * skill.dt
    assert res.phase("wait") == pytest.approx(wait) and wait == pytest.approx(0.5, abs=0.01)
    _check_program(skill, res, planned)
    assert abs(res.duration - wait - planned) < 0.1
    wc.release("human_right", "S1")
    wc.reset()


def test_the_program_follows_the_cell_and_the_robot(multi):
    """Poses come from the cell and speeds from the robot: a hand-over pose 5 cm further moves the place
    pose 5 cm, and a slower transit takes longer."""
    wc = multi
    wc.reset()
    pos, quat = wc.site_pose("handover")
    near, far = (handover(wc, "L", p, quat).plan() for p in (pos, pos + [0.0, 0.05, 0.0]))
    np.testing.assert_allclose(far.plan.place.pos - near.plan.place.pos, [0.0, 0.05, 0.0], atol=1e-12)
    slow = handover(wc, "L", pos, quat, params=SkillParams(limits=MotionLimits(transit_speed=0.15)))
    assert slow.planned_time() > near.planned_time + 1.0
