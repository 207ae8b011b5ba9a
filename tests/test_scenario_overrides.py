"""``--set`` addresses any field of a scenario by its dotted path, validated (issue 12 §6); the paper cells
keep the override names of earlier releases.

Only files are read and checked here: no workcell is simulated.
"""

from __future__ import annotations

import pytest
from own_product import write_product

from ergosim.cli import main
from ergosim.errors import ErgosimError
from ergosim.experiment.scenario import load_scenario
from ergosim.scenes import cell_document, cellfile
from ergosim.scenes.cellfile import cell_keys

# The names README and earlier releases gave (`ergosim run ... --set scene.NAME=...`), per paper cell.
PAPER_NAMES = {
    "kwear-validation": ("l_xy", "s1_xy", "s2_xy", "j_xy", "shelf_height", "shelf_low_height", "robot_base",
                         "robot_yaw", "bench_height", "worker_xy", "stature", "human_scale", "j_place_xy",
                         "assembly_xy", "carry_height", "seat_tolerance"),
    "multi-subject": ("l_xy", "s1_xy", "s2_xy", "j_xy", "robot_base", "robot_yaw", "side_table_height",
                      "side_table_center", "bench_height", "monitor_center", "handover_pos", "assembly_xy",
                      "assembly_yaw", "outfeed_xy", "stature", "human_scale", "worker_xy"),
}


@pytest.mark.parametrize("scene", sorted(PAPER_NAMES))
def test_the_paper_cells_keep_their_override_names(scene):
    doc, _ = cell_document(scene)
    aliases = doc["aliases"]
    for name in PAPER_NAMES[scene]:
        assert name in aliases, (scene, name)
        targets = aliases[name] if isinstance(aliases[name], list) else [aliases[name]]
        assert all(t in cell_keys(doc) for t in targets), (scene, name, targets)


@pytest.mark.parametrize(("scene", "key", "value", "field"), [
    ("multi-subject", "l_xy", "0.20,0.82", lambda c: c.part("L").xy),
    ("multi-subject", "s1_xy", "0.40,0.62", lambda c: c.part("S1").xy),
    ("multi-subject", "s2_xy", "0.52,0.66", lambda c: c.part("S2").xy),
    ("multi-subject", "j_xy", "0.32,0.68", lambda c: c.part("J").xy),
    ("multi-subject", "robot_base", "0.60,0.84,0.85", lambda c: c.robots[0].base),
    ("kwear-validation", "shelf_height", "1.6", lambda c: c.furniture[1].height),
    ("kwear-validation", "robot_base", "0.64,-0.30,1.05", lambda c: c.robots[0].base),
])
def test_a_paper_name_sets_its_field(scene, key, value, field):
    cell = load_scenario(scene, {f"scene.{key}": value}).cell()
    expected = tuple(float(v) for v in value.split(","))
    got = field(cell)
    assert (tuple(got) if isinstance(got, tuple) else (got,)) == expected


def test_one_name_may_set_several_fields():
    cell = load_scenario("multi-subject", {"scene.assembly_yaw": "-30"}).cell()
    assert {t.name: t.yaw for t in cell.targets}["assembly_area"] == -30.0
    assert {t.name: t.yaw for t in cell.targets}["outfeed"] == -30.0


@pytest.mark.parametrize(("key", "value", "check"), [
    # the workcell, by dotted path: any table of the file
    ("scene.parts.housing.xy", "0.70,-0.25", lambda sc: sc.cell().part("housing").xy == (0.70, -0.25)),
    ("scene.parts.housing.slots.top.at", "0,0,0.041",
     lambda sc: next(s for s in sc.cell().part("housing").slots if s.name == "top").at == (0.0, 0.0, 0.041)),
    ("scene.furniture.riser.half", "0.10,0.14,0.13",
     lambda sc: next(f for f in sc.cell().furniture if f.name == "riser").half == (0.10, 0.14, 0.13)),
    ("workcell.targets.outfeed.xy", "0.42,-0.40", lambda sc: sc.cell().targets[1].xy == (0.42, -0.40)),
    ("scene.actions.g6.turn_time", "3.5", lambda sc: sc.cell().action("g6").turn_time == 3.5),
    ("scene.robots.robot.yaw", "175", lambda sc: sc.cell().robots[0].yaw == 175.0),
    ("scene.worker.hand", "left", lambda sc: sc.cell().worker.hand == "left"),
    ("scene.views.top.distance", "1.8", lambda sc: sc.cell().view("top").distance == 1.8),
    ("scene.carry_height", "1.35", lambda sc: sc.cell().carry_height == 1.35),
    # the task, by dotted path
    ("task.agents.robot.cost", "3.5", lambda sc: sc.task().agents[1].cost == 3.5),
    ("task.liaisons.g4.agents", "human",
     lambda sc: all(o.agents == ("human",) for o in sc.task().operations if o.action == "g4")),
    ("task.liaisons.g3.cost.robot", "0.5",
     lambda sc: all(o.cost_of("robot") == 0.5 for o in sc.task().operations if o.action == "g3")),
    # the protocol, bare or by its table
    ("takt", "45", lambda sc: sc.protocol.pacing.takt == 45.0),
    ("protocol.v_th", "0.7", lambda sc: sc.protocol.cost.v_th == 0.7),
    ("modes", "hrc,r-only", lambda sc: sc.protocol.modes == ("hrc", "r-only")),
    # the scenario's own fields: another task or workcell
    ("workcell", "gearbox", lambda sc: sc.protocol.scene == "gearbox"),
])
def test_any_field_by_its_dotted_path(key, value, check):
    assert check(load_scenario("gearbox", {key: value}))


def test_another_task_and_workcell_by_file(tmp_path):
    scenario = write_product(tmp_path / "own")
    sc = load_scenario("gearbox", {"task": str(tmp_path / "own" / "bracket_task.toml"),
                                   "workcell": str(tmp_path / "own" / "bracket_cell.toml")})
    assert sc.protocol.task == "bracket" and sc.protocol.scene == "bracket-cell"
    assert sc.task().actions == ("b1", "b2", "b3", "b4", "b5")
    assert scenario.exists()


@pytest.mark.parametrize(("overrides", "needle"), [
    ({"scene.parts.housing.xyz": "1,2"}, "unknown key 'parts.housing.xyz'"),
    ({"scene.parts.nope.xy": "1,2"}, "unknown key 'parts.nope.xy'"),
    ({"scene.parts.housing.slots.nope.at": "0,0,0"}, "unknown key 'parts.housing.slots.nope.at'"),
    ({"scene.parts.housing.xy": "0.7"}, "has 1 value, expected 2"),
    ({"scene.worker.hand": "both"}, "must be right or left"),
    ({"task.agents.robot.cost": "cheap"}, "task.agents.robot.cost='cheap' is not a number"),
    ({"task.liaisons.g9.agents": "human"}, "unknown task field 'liaisons.g9.agents'"),
    ({"task.liaisons.g2.agents": "nobody"}, "unknown agent 'nobody'"),
    ({"task.liaisons.g1.agents": "robot"}, "its gripper cannot take housing"),
    ({"takt": "-1"}, "takt must be in (0, 3600] s, got -1"),
    ({"workcell": "nope"}, "unknown scene 'nope'"),
    ({"task": "nope.toml"}, "no such task file"),
    ({"protocol.scene": "x"}, "'protocol.scene' is a label"),
])
def test_every_override_is_validated(overrides, needle):
    with pytest.raises(ErgosimError) as err:  # ConfigError, or TaskFileError for the task's fields
        load_scenario("gearbox", overrides)
    assert needle in str(err.value), str(err.value)


def test_overrides_reach_the_command_line(capsys, tmp_path):
    code = main(["run", "gearbox", "--subjects", "1", "--reps", "1", "--jobs", "1", "--quiet", "--out",
                 str(tmp_path / "o"), "--set", "task.liaisons.g1.agents=robot"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "ergosim/data/tasks/gearbox.toml (with task.liaisons.g1.agents=robot): g1" in err, err


def test_workcell_overrides_are_parsed_once_and_win_over_a_subjects_body(monkeypatch):
    """The override strings are converted and checked when they are set, not again for every subject's
    workcell; a subject's body (typed fields) goes on top, except where an override set the same field."""
    sc = load_scenario("kwear-validation", {"scene.l_xy": "0.40,-0.12", "scene.worker.stature": "1.70"})
    coerced = []
    real = cellfile.override
    monkeypatch.setattr(cellfile, "override", lambda tree, doc, values, *a, **kw: coerced.extend(
        v for v in values.values() if isinstance(v, str)) or real(tree, doc, values, *a, **kw))
    for stature in (1.6, 1.8):
        cell = sc.cell(**{"worker.stature": stature, "worker.human_scale": (("upper_arm", 1.05),)})
        assert cell.part("L").xy == (0.40, -0.12) and cell.worker.stature == 1.70
        assert dict(cell.worker.human_scale) == {"upper_arm": 1.05}
    assert coerced == []
