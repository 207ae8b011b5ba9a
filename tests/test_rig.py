"""The twin's one session builder (ergosim/twin/rig.py): a session from a session config, a workcell and a
task, with no scenario, and the experiment's sessions built by it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ergosim.experiment.protocol import ScenarioConfig
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import rig_spec, scenario_subject, subject_session
from ergosim.planner.bundled import bundled_task
from ergosim.scenes import build_cell, load_cell
from ergosim.twin.protocol import PacingConfig, SessionConfig
from ergosim.twin.rig import RigSpec, ready_session, streams


def test_the_scenario_protocol_holds_a_sessions_fields_in_its_order():
    """``ScenarioConfig.session`` is every field of a :class:`SessionConfig`, taken from the protocol; the
    scenario adds its labels, modes and population."""
    session = [f.name for f in dataclasses.fields(SessionConfig)]
    scenario = [f.name for f in dataclasses.fields(ScenarioConfig)]
    assert [n for n in scenario if n in session] == session
    assert sorted(set(scenario) - set(session)) == ["modes", "population", "scene", "task"]
    cfg = ScenarioConfig.of("cell", "task", takt=41.0, v_th=0.7, execution="parallel", subjects=3)
    assert cfg.session == SessionConfig(pacing=PacingConfig(takt=41.0), cost=cfg.cost, team=cfg.team)


def test_the_streams_are_the_children_of_the_subjects_seed_sequence():
    children = np.random.SeedSequence([7, 2]).spawn(3)
    mine = streams(7, 2, (0, 1))
    assert [s.generate_state(4).tolist() for s in mine] == [c.generate_state(4).tolist() for c in children]
    assert streams(7, 2, (4,))[1].spawn_key == (5,)  # mode slot 4 draws from child 5


@pytest.mark.slow
def test_a_session_built_from_the_twin_alone_equals_the_experiments():
    """A workcell file, a bundled task and a session config build, with no scenario, the session the
    experiment builds for the same subject: the same allocations and the same ticks."""
    sc = load_scenario("multi-subject", {"repetitions": "1"})
    subject = scenario_subject(sc, 0, 0)
    spec = RigSpec(sc.protocol.session, lambda s: build_cell(load_cell("multi-subject", **s.workcell_fields)),
                   lambda: bundled_task("corner-joint:multi-subject"))
    alone = ready_session(spec, subject, 0, 0, "h-only", calibrate=False).run(1)
    ran = subject_session(sc, 0, 0, "h-only", calibrate=False).run(1)
    assert len(alone.allocations) == 5 and alone.allocations == ran.allocations
    assert alone.ticks.n > 100
    np.testing.assert_array_equal(alone.ticks.rows, ran.ticks.rows)
    assert rig_spec(sc).config == spec.config
