"""The schema layer (issue 37): value kinds, a table checked by pydantic, and the one dotted-path override
that the workcell, the task and the protocol share."""

from __future__ import annotations

from typing import Literal

import pytest

import ergosim.schema as schema
from ergosim.errors import ConfigError, TaskFileError
from ergosim.planner.task_overrides import apply_task_overrides, task_keys
from ergosim.scenes import cell_document
from ergosim.scenes.cell_schema import CELL, PartTable, ViewTable
from ergosim.scenes.cellfile import apply_cell_overrides
from ergosim.schema.document import check_table, override, paths
from ergosim.schema.values import AXIS, NUMBER, PAIRS, Invalid, Numbers, kind_of


def test_public_api_names_exist():
    assert all(hasattr(schema, name) for name in schema.__all__)


@pytest.mark.parametrize(("kind", "text", "value"), [
    (NUMBER, "1.5", 1.5), (Numbers(2), "0.2, 0.8", [0.2, 0.8]), (AXIS, "-y", "-y"),
    (AXIS, "0,0,2", [0, 0, 2]),
    (PAIRS, "upper_arm:1.1,forearm:0.9", [["upper_arm", 1.1], ["forearm", 0.9]]),
    (kind_of(tuple[float, float]), "1,2", (1.0, 2.0)), (kind_of(float | None), "none", None),
    (kind_of(Literal["a", "b"]), "b", "b"), (kind_of(bool), "off", False), (kind_of(int), "7", 7),
])
def test_an_override_string_becomes_the_value_of_its_kind(kind, text, value):
    assert kind.parse(text, "k") == value


@pytest.mark.parametrize(("kind", "text", "message"), [
    (NUMBER, "x", "k='x' is not a number"), (NUMBER, "inf", "k='inf' is not a finite number"),
    (Numbers(3), "1,2", "k='1,2' has 2 values, expected 3 (comma-separated, e.g. k=0,0,0)"),
    (Numbers(2), "1,,2", "k='1,,2' has an empty value between commas"),
    (PAIRS, "2", "k='2': expected name:value pairs separated by commas"),
    (kind_of(int), "2.5", "k='2.5' is not an integer"), (kind_of(bool), "maybe", "is not a boolean"),
    (kind_of(Literal["a", "b"]), "c", "k='c' is not one of a, b"),
])
def test_a_bad_override_string_is_one_message(kind, text, message):
    with pytest.raises(Invalid) as err:
        kind.parse(text, "k")
    assert message in err.value.what


def test_a_file_integer_of_400_digits_is_named_by_its_size():
    with pytest.raises(Invalid) as err:
        NUMBER.check(10**400, "mass")
    assert err.value.what == "mass=an integer of 401 digits is not a finite number"


def test_a_table_is_checked_by_its_model_and_errors_name_the_entry():
    assert check_table(ViewTable, {"azimuth": 1, "lookat": [0, 0, 1]}, "c.toml: views.v") == \
        {"azimuth": 1.0, "lookat": (0.0, 0.0, 1.0)}
    cases = [({"azimut": 1}, "c.toml: views.v: unknown key 'azimut'; valid keys: azimuth, elevation, "
                             "distance, lookat"),
             ({"azimuth": 1, "lookat": [0, 1]}, "c.toml: views.v.lookat: expected 3 numbers, got 2"),
             ({"elevation": float("nan"), "azimuth": "x"}, "c.toml: views.v.elevation: elevation=nan is not"),
             ([1], "c.toml: views.v: expected a table, got [1]")]
    for table, message in cases:
        with pytest.raises(ConfigError) as err:
            check_table(ViewTable, table, "c.toml: views.v")
        assert str(err.value).startswith(message), str(err.value)
    with pytest.raises(ConfigError, match="c.toml: parts.p: missing key 'shape'"):
        check_table(PartTable, {"mass": 1.0}, "c.toml: parts.p", required=("shape",))


def test_one_override_sets_a_workcell_field_a_slot_and_an_alias():
    doc, _ = cell_document("gearbox")
    keys = paths(CELL, doc)
    assert {"parts.housing.slots.top.at", "parts.housing.slots.top.axis", "worker.stature"} <= set(keys)
    assert not [k for k in keys if k.endswith((".type", ".slots.top.name")) or k == "name"]
    out = override(CELL, doc, {"parts.housing.slots.top.axis": "-z", "worker.stature": "1.7"}, "w")
    assert next(s for s in out["parts"]["housing"]["slots"] if s["name"] == "top")["axis"] == "-z"
    assert out["worker"]["stature"] == 1.7 and doc != out  # a copy; the document is left as it was
    with pytest.raises(ConfigError, match="w: axis='0,0' has 2 values, expected 3"):
        override(CELL, doc, {"parts.housing.slots.top.axis": "0,0"}, "w", said=lambda _p: "axis")
    kv, _ = cell_document("kwear-validation")
    assert apply_cell_overrides(kv, {"l_xy": "0.2,0.8"}, "w")["parts"]["L"]["xy"] == [0.2, 0.8]


def test_one_override_sets_a_task_cost_and_children():
    doc = {"name": "t", "parts": ["a", "b"], "agents": {"h": {"kind": "human"}, "r": {"kind": "robot"}},
           "operations": [{"name": "o", "joins": [["a"], ["b"]]}]}
    assert task_keys(doc) == ["name", "description", "parts", "agents.h.kind", "agents.h.cost",
                              "agents.r.kind", "agents.r.cost", "operations.o.action", "operations.o.joins",
                              "operations.o.father", "operations.o.agents", "operations.o.cost.h",
                              "operations.o.cost.r"]
    out = apply_task_overrides(doc, {"operations.o.cost.r": "2.5", "operations.o.joins": "a+b",
                                     "parts": "a,b"}, "t.toml")
    assert out["operations"][0]["cost"] == {"r": 2.5} and out["operations"][0]["joins"] == [["a", "b"]]
    with pytest.raises(TaskFileError, match="task.agents.h.cost='x' is not a number"):
        apply_task_overrides(doc, {"agents.h.cost": "x"}, "t.toml")
    with pytest.raises(TaskFileError, match="unknown task field 'operations.o.name'"):
        apply_task_overrides(doc, {"operations.o.name": "p"}, "t.toml")
