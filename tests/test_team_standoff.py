"""A parallel team that can no longer move ends its repetition as a standoff instead of running for ever.

Found with a user's own variant of the §7.2 cell in which the robot places and inserts the parts itself
(no hand-over poses): in parallel execution the robot bringing J to the assembly area stops under speed and
separation monitoring next to the idle worker, who keeps its posture; at HEAD the run never ended (a
12 × 10 team study ran for over half an hour before it was stopped). Now the repetition is abandoned after
:data:`~ergosim.twin.standoff.STANDOFF_TIMEOUT` with a message that says where and why.
"""

from __future__ import annotations

import csv
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.twin.standoff import STANDOFF_TIMEOUT, StandoffWatch

ROOT = Path(__file__).resolve().parents[1]
DT = 1.0 / 60.0


def _fake_team(worker_job=None, speed=0.0, moving=True, state="moving"):
    """What :meth:`StandoffWatch.check` reads: the worker's job, one robot job, the plant's clock."""
    data = SimpleNamespace(site_xpos=np.array([[0.1, 0.2, 1.0]]))
    cell = SimpleNamespace(data=data, robot=lambda name: SimpleNamespace(tcp=0))
    track = SimpleNamespace(moving=moving, speed=speed, cell=cell)
    job = SimpleNamespace(agent="robot", track=track, state=state, geom=SimpleNamespace(action="a1"))
    return SimpleNamespace(worker_job=worker_job, robot_jobs={"robot": job}, watch=StandoffWatch(),
                           plant=SimpleNamespace(ticks=0, dt_control=DT))


def _run_for(team, seconds: float):
    why = None
    for _ in range(int(round(seconds / DT))):
        team.plant.ticks += 1
        why = team.watch.check(team.plant, team.worker_job is None, team.robot_jobs.values())
        if why is not None:
            return why, team.plant.ticks * DT
    return why, None


def test_a_protective_stop_with_the_worker_idle_becomes_a_standoff_after_the_timeout():
    team = _fake_team()
    why, at = _run_for(team, STANDOFF_TIMEOUT + 1.0)
    assert at == pytest.approx(STANDOFF_TIMEOUT + DT, abs=1.5 * DT)
    assert why.startswith("standoff: robot, doing a1, has been in a protective stop for 10 s")
    assert "[0.1, 0.2, 1.0]" in why and "ISO/TS 15066" in why


def test_a_stop_while_the_worker_acts_or_a_robot_that_moves_again_is_no_standoff():
    team = _fake_team(worker_job=object())  # the worker moves: the separation may open again
    assert _run_for(team, 2 * STANDOFF_TIMEOUT) == (None, None)
    team = _fake_team()
    assert _run_for(team, STANDOFF_TIMEOUT - 1.0) == (None, None)
    team.robot_jobs["robot"].track.speed = 0.4  # slowed, not stopped: the count starts again
    assert _run_for(team, 1.0) == (None, None)
    team.robot_jobs["robot"].track.speed = 0.0
    assert _run_for(team, STANDOFF_TIMEOUT - 1.0) == (None, None)
    still = _fake_team(moving=False)  # holding a part out, the gripper: not a motion the monitor stops
    assert _run_for(still, 2 * STANDOFF_TIMEOUT) == (None, None)


def test_the_stop_on_the_way_home_is_named_so():
    why, _ = _run_for(_fake_team(state="homing"), STANDOFF_TIMEOUT + 1.0)
    assert why.startswith("standoff: robot, on its way home after a1,")


@pytest.mark.slow
def test_a_robot_placing_into_the_idle_workers_reach_ends_the_run_as_a_standoff(tmp_path, capsys):
    """The §7.2 cell without hand-over poses, robot only, in parallel: J's place stops the robot next to
    the worker; the run ends (exit 3, the repetition abandoned) and its files say why."""
    text = (ROOT / "ergosim/data/cells/multi-subject.toml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("handover = ")]
    assert len(lines) == len(text.splitlines()) - 4  # a1..a4 lose their hand-over poses
    cell = tmp_path / "robot_inserts.toml"
    cell.write_text("\n".join(lines) + "\n")
    out = tmp_path / "o"
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "2", "--mode", "r-only", "--jobs", "1",
                 "--quiet", "--set", "execution=parallel", "--set", f"workcell={cell}", "--out", str(out)])
    assert code == 3
    err = capsys.readouterr().err
    assert "abandoned" in err and "Traceback" not in err
    with (out / "failures.csv").open() as f:
        failures = list(csv.DictReader(f))
    assert [r["status"] for r in failures] == ["failed:standoff", "abandoned"]
    assert "standoff: robot, doing a1, has been in a protective stop" in failures[1]["message"]
    t_end = float(failures[0]["time"])
    assert STANDOFF_TIMEOUT < t_end < STANDOFF_TIMEOUT + 30.0  # ended soon after the stop, not at 180 s
    with (out / "allocations.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["action"] == "a1" and rows[0]["status"] == "failed:standoff"
