"""Liaison-based generation (Homem de Mello & Sanderson) against an exhaustive enumeration."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.errors import TaskFileError
from ergosim.planner import generate_task
from ergosim.planner.liaisons import Liaison, _connected, _splits, child_label, generate_operations


def _brute_splits(father, adj):
    first = father & -father
    out = []
    sub = (father - 1) & father
    while sub:
        if sub & first and _connected(sub, adj) and _connected(father & ~sub, adj):
            out.append(sub)
        sub = (sub - 1) & father
    return sorted(out)


@st.composite
def graphs(draw):
    n = draw(st.integers(2, 9))
    edges = draw(st.sets(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)), max_size=3 * n))
    adj = [0] * n
    for a, b in edges:
        if a != b:
            adj[a] |= 1 << b
            adj[b] |= 1 << a
    father = draw(st.integers(1, (1 << n) - 1))
    return father, adj


@settings(max_examples=300, deadline=None)
@given(graphs())
def test_split_search_finds_exactly_the_connected_bipartitions(case):
    father, adj = case
    expected = _brute_splits(father, adj) if _connected(father, adj) else []
    found = _splits(father, adj) if _connected(father, adj) and father.bit_count() > 1 else []
    assert sorted(found) == expected
    assert len(set(found)) == len(found)


def test_child_labels():
    parts = ["p1", "p2", "p3", "p4", "p5", "p6"]
    assert child_label(parts, 0b000111) == "p1-p2-p3"
    assert child_label(parts, 0b001111) == "p1..p4"
    assert child_label(parts, 0b110111) == "p1-p2-p3-p5-p6"
    assert child_label(parts, 0b111101) == "p1-p3..p6"


def _liaisons(pairs, names=("h",)):
    return [Liaison(a, b, f"{a}{b}", names, (1.0,) * len(names)) for a, b in pairs]


def test_cycle_of_four():
    parts = ["A", "B", "C", "D"]
    ops = generate_operations(parts, _liaisons([("A", "B"), ("B", "C"), ("C", "D"), ("A", "D")]), [], ["h"])
    fathers = {op.father for op, _ in ops}
    # connected proper sub-assemblies of a 4-cycle: 4 pairs, 4 triples, plus the root
    assert len(fathers) == 9
    root_ops = [op for op, _ in ops if op.father == tuple(parts)]
    # the root splits into 2 pairs (2 ways) or a triple and a single (4 ways); each cuts two liaisons
    assert len(root_ops) == 6 and all("+" in op.action for op in root_ops)


def test_precedence_means_inside_the_same_sub_assembly():
    parts = ["A", "B", "C", "D"]
    liaisons = _liaisons([("A", "B"), ("B", "C"), ("C", "D")])
    ops = generate_operations(parts, liaisons, [("AB", "CD")], ["h"])
    for op, _ in ops:
        if op.action == "CD":  # C-D may only be made once A-B is in the same sub-assembly
            assert {"A", "B"} <= set(op.father)
    assert [op.name for op, _ in ops if op.action == "CD"] == ["A-B-C+D"]


def test_agents_and_costs_of_operations_making_several_liaisons():
    liaisons = [
        Liaison("A", "B", "x", ("h", "r"), (1.0, 2.0)),
        Liaison("B", "C", "y", ("r",), (5.0,)),
        Liaison("A", "C", "x", ("h", "r"), (1.0, 3.0)),
    ]
    ops = {op.name: op for op, _ in generate_operations(["A", "B", "C"], liaisons, [], ["h", "r"])}
    assert (ops["A+B-C"].action, ops["A+B-C"].agents, ops["A+B-C"].costs) == ("x", ("h", "r"), (2.0, 5.0))
    assert (ops["A-B+C"].action, ops["A-B+C"].agents, ops["A-B+C"].costs) == ("y+x", ("r",), (8.0,))


def test_cycle_in_precedence_is_an_error():
    with pytest.raises(TaskFileError, match="cycle"):
        generate_operations(
            ["A", "B", "C"],
            _liaisons([("A", "B"), ("B", "C")]),
            [("AB", "BC"), ("BC", "AB")],
            ["h"],
            where="t",
        )


# -- issue 27: scarce:N built directly, and splits without recursion -----------------------------------------
def test_scarce_built_directly_equals_the_liaison_generator():
    """generate_task builds scarce:N's operations directly (the generator is O(N⁴) on its star of liaisons);
    they are the generator's, operation for operation, order and costs included."""
    for n in (2, 3, 7, 25):
        parts = [f"p{i}" for i in range(1, n + 1)]
        names = ("human", "robot1", "robot2")
        liaisons = [Liaison(parts[0], parts[i], f"l{i}", names, (1.0,) * 3) for i in range(1, n)]
        precedence = [(f"l{i}", f"l{i + 1}") for i in range(1, n - 1)]
        reference = [op for op, _ in generate_operations(parts, liaisons, precedence, names)]
        built = generate_task(f"scarce:{n}", agents=3).operations
        assert [(o.name, o.action, o.father, o.children) for o in built] == [
            (o.name, o.action, o.father, o.children) for o in reference]


@pytest.mark.slow
def test_splits_of_a_long_chain_need_no_recursion():
    """A chain of 3000 parts: its root has 2999 splits, found 3000 levels deep (RecursionError at HEAD)."""
    n = 3000
    adj = [(1 << (i - 1) if i else 0) | (1 << (i + 1) if i + 1 < n else 0) for i in range(n)]
    found = _splits((1 << n) - 1, adj)
    assert len(found) == n - 1 and found[0] == 1 and found[-1] == (1 << (n - 1)) - 1
