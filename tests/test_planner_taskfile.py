"""Task files: both forms, mixing, the bundled files, and one clear message for each kind of mistake."""

from __future__ import annotations

import textwrap
from importlib import resources

import pytest

from ergosim.errors import InfeasiblePlanError, TaskFileError
from ergosim.planner import BUNDLED_TASKS, bundled_task, load_task, parse_task

HEAD = """
name = "example"
parts = ["A", "B", "C"]
[agents.human]
kind = "human"
[agents.robot]
kind = "robot"
cost = 2.5
"""

EXPLICIT = (
    HEAD
    + """
[[operations]]
name = "AB"
action = "join-AB"
joins = [["A"], ["B"]]
cost = { human = 1.0, robot = 2.5 }
agents = ["human", "robot"]
[[operations]]
name = "AB+C"
action = "add-C"
joins = [["A", "B"], ["C"]]
cost = { human = 4.0 }
[[operations]]
name = "ABC"
action = "all-at-once"
joins = [["A"], ["B"], ["C"]]
agents = ["robot"]
cost = { robot = 3.0 }
"""
)


def write(tmp_path, text, name="task.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_explicit_form(tmp_path):
    g = load_task(write(tmp_path, EXPLICIT))
    assert g.name == "example" and g.parts == ("A", "B", "C")
    assert g.actions == ("join-AB", "add-C", "all-at-once")
    assert g.n_nodes == 5 and g.n_hyperarcs == 2 + 2 + 1
    assert g.operation("AB+C").costs == (4.0, 2.5)  # robot falls back to its default cost
    plan = g.plan()
    assert plan.cost == 3.0 and [(s.operation, s.agent) for s in plan.steps] == [("ABC", "robot")]
    assert g.plan(pruned={("all-at-once", "robot")}).cost == 3.5  # AB by human, AB+C by robot


def test_liaison_form_with_precedence():
    g = parse_task(
        HEAD
        + """
[[liaisons]]
parts = ["A", "B"]
action = "ab"
[[liaisons]]
parts = ["B", "C"]
action = "bc"
cost = { robot = 0.5 }
[[liaisons]]
parts = ["A", "C"]
action = "ac"
agents = ["human"]
"""
    )
    # triangle: every subset is connected; 3 + 3 + 1 nodes, each pair 1 split, the root 3 splits
    assert g.n_nodes == 7 and len(g.operations) == 6
    by_father = {op.name: op for op in g.operations}
    assert by_father["A+B-C"].action == "ab+ac"  # the root split cuts two liaisons at once
    assert by_father["A+B-C"].agents == ("human",)  # only the human may make 'ac'
    assert by_father["B+C"].costs == (1.0, 0.5)
    constrained = parse_task(
        HEAD
        + """
[[liaisons]]
parts = ["A", "B"]
action = "ab"
[[liaisons]]
parts = ["B", "C"]
action = "bc"
[[precedence]]
before = "bc"
after = ["ab"]
"""
    )
    assert [op.name for op in constrained.operations] == ["B+C", "A+B-C"]


def test_mixed_forms_expand_children_of_explicit_operations():
    g = parse_task(
        HEAD.replace('["A", "B", "C"]', '["A", "B", "C", "tray"]')
        + """
[[liaisons]]
parts = ["A", "B"]
action = "ab"
[[liaisons]]
parts = ["B", "C"]
action = "bc"
[[operations]]
name = "stow"
joins = [["A", "B", "C"], ["tray"]]
agents = ["robot"]
"""
    )
    assert g.actions == ("ab", "bc", "stow")
    assert [op.name for op in g.operations] == ["stow", "A+B", "B+C", "A+B-C", "A-B+C"]
    assert g.plan().steps[-1].operation == "stow"


@pytest.mark.parametrize("variant", ["multi-subject", "kwear-validation"])
def test_bundled_files_load_through_the_parser(variant):
    name = f"corner-joint/{variant}.toml"
    text = resources.files("ergosim").joinpath("data", "tasks", name).read_text(encoding="utf-8")
    g = parse_task(text, source=name)
    bundled = bundled_task(f"corner-joint:{variant}")
    assert g.name == bundled.name == f"corner-joint-{variant}"
    assert g.operations == bundled.operations and g.parts == ("area", "J", "L", "S1", "S2", "away")
    assert {a.name: a.cost for a in g.agents}["robot"] == (2.5 if variant == "multi-subject" else 50.0)


def test_bundled_names_come_from_the_data_folder():
    assert {"corner-joint", "corner-joint:multi-subject", "corner-joint:kwear-validation", "gearbox"} <= set(
        BUNDLED_TASKS)
    assert bundled_task("corner-joint").operations == bundled_task("corner-joint:multi-subject").operations


def error_text(tmp_path, text, kind=TaskFileError):
    path = write(tmp_path, text, "bad.toml")
    with pytest.raises(kind) as err:
        load_task(path)
    message = str(err.value)
    assert "\n" not in message and message.startswith(str(path))
    return message


def test_toml_syntax_error_has_line_and_column(tmp_path):
    message = error_text(tmp_path, 'name = "x"\nparts = ["A", "B"\n[agents.h]\n')
    assert "invalid TOML" in message and "line 3" in message and "column" in message


@pytest.mark.parametrize(
    ("change", "entry", "problem"),
    [
        ('joins = [["A"], ["B"]]', "operations[0] 'AB'", "unknown part 'Z'"),
        ('action = "join-AB"', "operations[1]", "duplicate operation name 'AB'"),
        ('joins = [["A"], ["B"]]', "operations[0] 'AB'", "children overlap: part(s) [A]"),
        (
            'joins = [["A"], ["B"]]',
            "operations[0] 'AB'",
            "father [A B C] is not the union of the children [A B]",
        ),
        ('agents = ["human", "robot"]', "operations[0] 'AB'", "unknown agent 'cobot'"),
        (
            "cost = { human = 1.0, robot = 2.5 }",
            "operations[0] 'AB'",
            "cost.human must be finite and >= 0, got -1.0",
        ),
        (
            "cost = { human = 1.0, robot = 2.5 }",
            "operations[0] 'AB'",
            "cost.robot must be finite and >= 0, got inf",
        ),
        (
            "cost = { human = 1.0, robot = 2.5 }",
            "operations[0] 'AB'",
            "cost.robot must be finite and >= 0, got nan",
        ),
    ],
)
def test_bad_operations(tmp_path, change, entry, problem):
    replacement = {
        "unknown part 'Z'": 'joins = [["A"], ["Z"]]',
        "duplicate operation name 'AB'": 'action = "join-AB"\nname = "AB"',
        "children overlap: part(s) [A]": 'joins = [["A"], ["A", "B"]]',
        "father [A B C]": 'joins = [["A"], ["B"]]\nfather = ["A", "B", "C"]',
        "unknown agent 'cobot'": 'agents = ["human", "cobot"]',
        "cost.human": "cost = { human = -1.0, robot = 2.5 }",
        "got inf": "cost = { human = 1.0, robot = inf }",
        "got nan": "cost = { human = 1.0, robot = nan }",
    }
    new = next(v for k, v in replacement.items() if k in problem)
    text = EXPLICIT.replace(change, new, 1)
    if "duplicate" in problem:  # rename the second operation to AB
        text = EXPLICIT.replace('name = "AB+C"', 'name = "AB"')
    message = error_text(tmp_path, text)
    assert f"bad.toml: {entry}" in message and problem in message, message


def test_duplicate_part_and_liaison(tmp_path):
    message = error_text(tmp_path, EXPLICIT.replace('["A", "B", "C"]', '["A", "B", "A"]'))
    assert "bad.toml: parts[2]: duplicate part name 'A'" in message
    message = error_text(
        tmp_path,
        HEAD
        + '[[liaisons]]\nparts = ["A", "B"]\naction = "x"\n[[liaisons]]\nparts = ["B", "A"]\naction = "y"\n',
    )
    assert "liaisons[1]: duplicate liaison between 'A' and 'B' (first at liaisons[0])" in message


def test_unknown_agent_kind_and_keys(tmp_path):
    assert "agents.human: kind must be 'human' or 'robot', got 'cyborg'" in error_text(
        tmp_path, EXPLICIT.replace('kind = "human"', 'kind = "cyborg"')
    )
    assert "operations[0] 'AB': unknown key 'cots'" in error_text(
        tmp_path, EXPLICIT.replace("cost = { human = 1.0, robot = 2.5 }", "cots = { human = 1.0 }")
    )
    assert "bad.toml: unknown key 'step'" in error_text(tmp_path, "step = 1\n" + EXPLICIT)
    assert "agents.robot: cost must be finite and >= 0, got -2.5" in error_text(
        tmp_path, EXPLICIT.replace("cost = 2.5", "cost = -2.5")
    )


def test_precedence_errors(tmp_path):
    liaisons = (
        HEAD
        + '[[liaisons]]\nparts = ["A", "B"]\naction = "ab"\n[[liaisons]]\nparts = ["B", "C"]\naction = "bc"\n'
    )
    cycle = (
        liaisons
        + '[[precedence]]\nbefore = "ab"\nafter = "bc"\n[[precedence]]\nbefore = "bc"\nafter = "ab"\n'
    )
    assert "bad.toml: precedence: precedence constraints form a cycle through action 'ab'" in error_text(
        tmp_path, cycle
    )
    unknown = liaisons + '[[precedence]]\nbefore = "ab"\nafter = "ca"\n'
    assert "precedence[0]: unknown action 'ca' in after" in error_text(tmp_path, unknown)


def test_no_feasible_plan_names_the_operation_no_agent_may_do(tmp_path):
    text = EXPLICIT.replace('agents = ["robot"]\ncost = { robot = 3.0 }', "agents = []").replace(
        "cost = { human = 4.0 }\n", "agents = []\n"
    )
    message = error_text(tmp_path, text, InfeasiblePlanError)
    assert "bad.toml: operations[1] 'AB+C': no feasible plan: no agent may do operation 'AB+C'" in message
    assert "nor any of the other 1 operation(s) forming [A B C]" in message


def test_no_feasible_plan_names_the_part_that_can_never_be_joined(tmp_path):
    text = EXPLICIT.replace('["A", "B", "C"]', '["A", "B", "C", "D"]', 1)
    message = error_text(tmp_path, text, InfeasiblePlanError)
    assert "bad.toml: parts[3] 'D': no feasible plan: part 'D' can never be joined" in message
    liaisons = HEAD.replace('["A", "B", "C"]', '["A", "B", "C", "D"]') + (
        '[[liaisons]]\nparts = ["A", "B"]\naction = "ab"\n[[liaisons]]\nparts = ["C", "D"]\naction = "cd"\n'
    )
    message = error_text(tmp_path, liaisons, InfeasiblePlanError)
    assert (
        "bad.toml: liaisons: no feasible plan: the liaisons leave the parts in unconnected groups [A B] [C D]"
        in (message)
    )


def test_no_feasible_plan_when_precedence_blocks_everything(tmp_path):
    text = HEAD + (
        '[[liaisons]]\nparts = ["A", "B"]\naction = "ab"\n[[liaisons]]\nparts = ["B", "C"]\naction = "bc"\n'
        '[[liaisons]]\nparts = ["A", "C"]\naction = "ac"\n'
        '[[precedence]]\nbefore = "ab"\nafter = "bc"\n[[precedence]]\nbefore = "bc"\nafter = "ac"\n'
    )
    # 'ab' before 'bc' before 'ac', but the last join of a triangle always makes two liaisons at once
    message = error_text(tmp_path, text, InfeasiblePlanError)
    assert "no feasible plan: no operation joins the full assembly [A B C]" in message


def test_missing_file_and_unreachable_operation(tmp_path):
    with pytest.raises(TaskFileError, match="no such task file"):
        load_task(tmp_path / "nope.toml")
    text = EXPLICIT + '[[operations]]\nname = "BC"\njoins = [["B"], ["C"]]\n'
    assert "operations[3] 'BC': operation 'BC' can never be used" in error_text(tmp_path, text)
