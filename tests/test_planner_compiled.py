"""The compiled AND/OR graph: frozen once built, and its accessors against brute force on random graphs."""

from __future__ import annotations

import ast
import itertools
import pickle
from pathlib import Path

import numpy as np
import pytest
from aog_strategies import SETTINGS, calls, explicit_graphs, liaison_graphs
from hypothesis import given
from hypothesis import strategies as st

from ergosim.errors import ConfigError
from ergosim.planner import AndOrGraph, CompiledGraph, bundled_task, generate_task
from ergosim.planner.call_inputs import configuration

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def corner():
    return bundled_task("corner-joint")


def test_a_graph_is_frozen_once_built(corner):
    assert isinstance(corner, CompiledGraph)
    with pytest.raises(AttributeError, match="frozen"):
        corner.root = 0
    with pytest.raises(AttributeError, match="frozen"):
        del corner.parts
    with pytest.raises(TypeError):
        corner.op_index["x"] = 0
    with pytest.raises(TypeError):
        corner.key_hyperarcs[("a1", "human")] = np.zeros(1)
    table = corner.op_table
    arrays = [corner.layout.cost, corner.layout.op, corner.layout.levels[0].children, table.op_children,
              table.op_perm, table.levels[0][0], next(iter(corner.key_hyperarcs.values())),
              next(iter(table.action_ops.values()))]
    for a in arrays:
        with pytest.raises(ValueError, match="read-only"):
            a[0] = a[0]
    assert corner.op_table is table and corner.node_edges is corner.node_edges  # derived once


def test_a_pickled_graph_plans_the_same(corner):
    """A graph crosses to a spawned worker as its task and is compiled again there."""
    copy = pickle.loads(pickle.dumps(corner))
    assert type(copy) is AndOrGraph and copy is not corner
    assert (copy.name, copy.source, copy.parts, copy.agents, copy.operations, copy.actions) == (
        corner.name, corner.source, corner.parts, corner.agents, corner.operations, corner.actions)
    costs = {("a2", "human"): 3.0, ("a4", "robot"): 0.2}
    assert copy.plan(done=["area+J"], costs=costs) == corner.plan(done=["area+J"], costs=costs)
    assert copy.where("area+J") == corner.where("area+J")


def test_the_corner_joint_structure(corner):
    n = {parts: i for i, parts in enumerate(corner.nodes)}
    insert_l = corner.op_index["area-J+L"]
    assert corner.children(insert_l) == (n[("area", "J")], n[("L",)])
    assert corner.father(insert_l) == n[("area", "J", "L")]
    assert corner.root == corner.n_nodes - 1 and corner.node_parts(corner.root) == corner.parts
    assert corner.leaves == tuple(n[(p,)] for p in corner.parts)
    assert corner.parents[n[("area", "J")]] == tuple(corner.op_index[o] for o in
                                                    ("area-J+L", "area-J+S1", "area-J+S2"))
    assert corner.node_with(corner.leaves, "S1") == n[("S1",)]
    assert corner.node_with([n[("area", "J", "L")], n[("S1",)]], "L") == n[("area", "J", "L")]
    with pytest.raises(ConfigError, match="unknown part 'X'"):
        corner.node_with(corner.leaves, "X")
    present = np.zeros(corner.n_nodes + 1, dtype=bool)
    present[list(corner.leaves) + [-1]] = True
    assert corner.ready(present).tolist() == [corner.op_index["area+J"]]  # a1 first: J onto the area
    # L, S1 and S2 go into J in any order; J comes first and the hand-over last
    assert corner.free_order_groups == (("a1",), ("a2", "a3", "a4"), ("a5",))
    assert corner.may_precede("a1", "a2") and not corner.may_precede("a2", "a1")
    assert corner.may_precede("a3", "a2") and corner.may_precede("a2", "a3")


@pytest.mark.parametrize(("spec", "groups"), [("sequential:6", 1), ("scarce:6", 5)])
def test_free_order_groups_of_the_generated_tasks(spec, groups):
    """sequential:N has no precedence (every liaison may go first); scarce:N orders every liaison."""
    graph = generate_task(spec)
    assert len(graph.free_order_groups) == groups
    assert sum(graph.free_order_groups, ()) == graph.actions


def _plan_trees(graph):
    """Brute force: every complete plan from the parts, as {operation index: its descendants}."""
    by_father = {}
    for i, op in enumerate(graph.operations):
        by_father.setdefault(op.father, []).append(i)

    def trees(node):
        if len(node) == 1:
            return [{}]
        out = []
        for o in by_father.get(node, ()):
            for combo in itertools.product(*(trees(c) for c in graph.operations[o].children)):
                tree = {k: v for t in combo for k, v in t.items()}
                tree[o] = set().union(*(set(t) for t in combo))
                out.append(tree)
        return out

    return trees(graph.parts)


def _check_structure(graph):
    for op in range(len(graph.operations)):
        assert graph.father(op) in range(graph.n_nodes)
        assert all(op in graph.parents[c] and c < graph.father(op) for c in graph.children(op))
        assert op in graph.node_ops[graph.father(op)]
        np.testing.assert_array_equal(np.sort(graph.op_table.hyperarcs(op)),
                                      np.flatnonzero(graph.layout.op == op))
    for node, edges in enumerate(graph.node_edges):
        assert [h for h, _ in edges] == np.flatnonzero(graph.layout.father == node).tolist()
        for h, bits in edges:
            assert bits == sum(1 << c for c in set(graph.children(int(graph.layout.op[h]))))
    # x may come first when some plan has an x operation that is not an ancestor of a y operation: every
    # plan's pairs collected once (a plan has at most one operation per part split, so this is quadratic
    # in its size, where asking every pair of actions of every plan was not)
    action = [op.action for op in graph.operations]
    may_first = {(action[a], action[b]) for t in _plan_trees(graph) for a in t for b in t
                 if action[a] != action[b] and b not in t[a]}
    for x, y in itertools.permutations(graph.actions, 2):
        assert graph.may_precede(x, y) == ((x, y) in may_first), (x, y)
    for group in graph.free_order_groups:  # every action of a group of two or more is linked to another
        linked = {x for pair in itertools.combinations(group, 2)
                  if graph.may_precede(*pair) and graph.may_precede(*pair[::-1]) for x in pair}
        assert len(group) == 1 or linked == set(group), group


def _check_ready(graph, done):
    config = configuration(graph, done)
    present = np.zeros(graph.n_nodes + 1, dtype=bool)
    present[config] = True
    present[-1] = True
    expected = [i for i in range(len(graph.operations)) if set(graph.children(i)) <= set(config.tolist())]
    assert graph.ready(present).tolist() == expected


@pytest.mark.parametrize("graphs", [explicit_graphs, liaison_graphs])
@SETTINGS
@given(data=st.data())
def test_accessors_match_brute_force_on_random_graphs(graphs, data):
    graph = data.draw(graphs())
    _check_structure(graph)
    done, _, _ = data.draw(calls(graph))
    _check_ready(graph, done)


def _private_reads(path: Path) -> list[str]:
    """``x._name`` reads where ``x`` is not ``self`` or ``cls``."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if (isinstance(node, ast.Attribute) and node.attr.startswith("_") and not node.attr.startswith("__")
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))):
            out.append(f"{path.name}:{node.lineno} {ast.unparse(node)}")
    return out


def test_the_planners_read_the_compiled_graph_through_its_public_attributes():
    planner = sorted((ROOT / "ergosim" / "planner").glob("*.py"))
    files = planner + sorted(ROOT.glob("ergosim/**/team_board.py"))
    assert len(files) > 20
    assert [r for f in files for r in _private_reads(f)] == []


def _planner_imports(path: Path) -> set[str]:
    """The ``ergosim.planner`` modules ``path`` imports (the package's ``__init__`` aside)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module == "ergosim.planner":
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("ergosim.planner."):
            names.add(node.module.split(".")[2])
        elif isinstance(node, ast.Import):
            names |= {a.name.split(".")[2] for a in node.names if a.name.startswith("ergosim.planner.")}
    return names


def test_the_planner_has_no_import_circle():
    """Every module of the planner can be ordered so that each imports only modules before it."""
    modules = {p.stem: p for p in (ROOT / "ergosim" / "planner").glob("*.py") if p.stem != "__init__"}
    imports = {m: _planner_imports(p) & modules.keys() - {m} for m, p in modules.items()}
    assert imports["graph"] >= {"bottom_up", "paper_search"}  # the check sees the imports
    ordered: list[str] = []
    while len(ordered) < len(modules):
        ready = sorted(m for m in modules if m not in ordered and imports[m] <= set(ordered))
        assert ready, f"import circle among {sorted(set(modules) - set(ordered))}"
        ordered += ready
