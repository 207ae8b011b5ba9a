"""The robot's side of the loop: its two speeds as protocol fields, and the robot-only assembly of §7.2."""

import json

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.robot_timing import ActionTiming, RobotOnlyRun, robot_only_runs, timing_summary
from ergosim.experiment.scenario import load_scenario, scenario_config
from ergosim.experiment.subject import rig_spec
from ergosim.robot.status import SKILL_PHASES, SkillResult, SkillStatus
from ergosim.twin.rig import build_rig
from ergosim.twin.robot_track import RobotTrack
from ergosim.worker.subjects import make_subjects


def _one_line_error(capsys, code: int, *needles: str) -> None:
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("ergosim: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


def test_both_speeds_are_protocol_fields_with_their_sources():
    cfg = scenario_config("multi-subject")
    assert cfg.robot.ee_speed == 0.05 and cfg.robot.transit_speed == 0.25  # paper §7.2; ISO 10218-1:2011 §5.6
    sc = load_scenario("multi-subject", {"transit_speed": "0.3", "ee_speed": "0.04"})
    assert (sc.protocol.robot.ee_speed, sc.protocol.robot.transit_speed) == (0.04, 0.3)
    rig = build_rig(rig_spec(sc), make_subjects(1, 0)[0], np.random.default_rng(0))
    limits = rig.robot.params.limits
    assert (limits.speed, limits.transit_speed) == (0.04, 0.3)  # the protocol reaches the skills
    track = RobotTrack(rig.cell)
    assert (track.params.limits.speed, track.params.limits.transit_speed) == (0.05, 0.25)


@pytest.mark.parametrize("setting, needle", [
    ("transit_speed=5", "transit_speed must be at most 1.7 m/s (the panda's Cartesian limit, robot 'robot'), "
                        "got 5"),
    ("transit_speed=0", "transit_speed must be at least 0.001 m/s, got 0"),
    ("transit_speed=fast", "transit_speed='fast' is not a number"),
    ("ee_speed=0.3", "ee_speed (0.3 m/s, contact-critical motion) must not exceed transit_speed (0.25 m/s"),
])
def test_bad_speeds_are_one_line_errors(capsys, tmp_path, setting, needle):
    code = main(["run", "multi-subject", "--quiet", "--out", str(tmp_path / "n"), "--set", setting])
    _one_line_error(capsys, code, needle)
    assert not (tmp_path / "n").exists()


def test_a_scenario_file_names_where_a_bad_speed_is(tmp_path):
    path = tmp_path / "fast.toml"
    path.write_text('task = "corner-joint:multi-subject"\nworkcell = "multi-subject"\n[protocol]\n'
                    'subjects = 1\nrepetitions = 1\nmodes = ["r-only"]\nrobot_cost = 2.5\n'
                    'transit_speed = 2.0\n')
    with pytest.raises(ConfigError, match="transit_speed must be at most 1.7 m/s") as err:
        load_scenario(str(path))
    assert "fast.toml: protocol" in str(err.value)


@pytest.mark.slow
def test_the_robot_only_assembly_of_the_multi_subject_cell():
    """Paper §7.2: the robot hands a1-a4 over, presenting each part at its target (the worker pushes it
    home and does a5). At 0.05 m/s in the contact zones and 0.25 m/s in transit each hand-over takes the
    robot 8-14 s up to the worker's take (43 s for the four, the paper's 38 s within 20 %); the whole
    repetition, with the worker's part serial to the robot's, about a minute (it took 144 s at 0.05 m/s
    throughout)."""
    sc = load_scenario("multi-subject")
    runs = robot_only_runs(sc, 2)
    for run in runs:
        assert run.outcome == "completed"
        assert [(a.agent, a.status) for a in run.actions] == [("robot", "done")] * 4 + [("human", "done")]
        robot = [a.robot_time for a in run.actions[:4]]  # the robot's own time per action
        # a2's L lies near the robot's base in the calibrated layout: the wrist turns most there
        assert all(10.0 < t < 21.0 for t in robot), robot
        assert 45.0 < run.robot_time < 65.0
        assert run.robot_time < run.repetition < 100.0
        # reach, grasp and carry up to the handover pose: the part of the robot's time the worker waits for.
        # The paper's fact is the sum (§7.2: about 38 s for a1-a4; the fidelity row's ±20 %); each action
        # starts from the park pose turned away from the worker, a2's L furthest round (13.3-13.4 s)
        assert all(6.0 < a.delivery < 15.0 for a in run.actions[:4])
        assert 0.8 * 38.0 < sum(a.delivery for a in run.actions[:4]) < 1.2 * 38.0
        assert 0.6 * run.robot_time < run.delivery < 0.8 * run.robot_time
        for a in run.actions[:4]:
            r = a.robot
            assert r.ok and {n for n, _ in r.phases} == set(SKILL_PHASES)
            # the action ends when the worker has inserted the part, which the robot had brought and let go
            # of; its way home may run on into the next action
            assert r.arrival + r.phase("wait") <= a.duration + 1e-9
            # transit from the park pose, turned away from the worker: a2's, to L at the side table's far
            # end and on to J's upper hollow on the bench, is the longest (9.8-10.0 s at 0.25 m/s)
            assert 2.0 < r.phase("contact") < 5.0 and 3.0 < r.phase("transit") < 11.0
    # the transit speed is what the robot's time is most sensitive to; ±10 % moves it by a few seconds
    for speed, sign in (("0.275", -1), ("0.225", 1)):
        other = robot_only_runs(sc.with_overrides({"transit_speed": speed}), 1)[0]
        assert 0.5 < sign * (other.robot_time - runs[0].robot_time) < 6.0
    summary = timing_summary(runs)
    assert summary["completed"] == 2 and set(summary["actions"]) == {"a1", "a2", "a3", "a4", "a5"}
    assert summary["repetition_mean_s"] == pytest.approx(np.mean([r.repetition for r in runs]))


def test_a_robot_action_that_failed_is_counted_not_averaged():
    """A robot action that never delivered its part (arrival NaN) enters no phase or delivery mean: the
    summary says how many failed and stays valid JSON (a NaN made the fidelity report crash)."""
    ok = SkillResult("pick_place", "J", SkillStatus.OK, "", 12.0, phases=(("transit", 8.0), ("contact", 4.0)),
                     arrival=9.0)
    failed = SkillResult("pick_place", "L", SkillStatus.UNREACHABLE, "no IK", 3.0, phases=(("transit", 3.0),))
    actions = (ActionTiming("a1", "robot", "done", 12.5, ok),
               ActionTiming("a2", "robot", "failed", 3.0, failed),
               ActionTiming("a5", "human", "done", 3.0, None))
    summary = timing_summary([RobotOnlyRun(0, "completed", 18.5, actions)])
    assert summary["robot_failures"] == 1 and summary["delivery_mean_s"] == 9.0
    assert summary["actions"]["a2"] == {"duration": 3.0}
    json.dumps(summary, allow_nan=False)
