"""--set overrides: typed conversion and one-line errors for bad keys and values."""

from __future__ import annotations

import dataclasses
from typing import Literal

import pytest

from ergosim.errors import ConfigError, TaskFileError
from ergosim.overrides import apply_overrides, finite_float, parse_assignments


@dataclasses.dataclass(frozen=True)
class _Cfg:
    takt: float = 38.0
    reps: int = 10
    mode: Literal["hrc", "h-only"] = "hrc"
    spawn: bool = False
    modes: tuple[str, ...] = ("hrc", "h-only")
    cap: float | None = None

    def validate(self, where: str = "") -> None:
        if self.takt <= 0:
            raise ConfigError(f"takt must be > 0 s, got {self.takt}", where=where)


def test_parse_assignments_splits_on_first_equals():
    assert parse_assignments(["a=1", "scene.b = x=y"]) == {"a": "1", "scene.b": "x=y"}


@pytest.mark.parametrize("bad", ["novalue", "=3", ""])
def test_parse_assignments_rejects_malformed(bad):
    with pytest.raises(ConfigError, match="expected KEY=VALUE"):
        parse_assignments([bad])


def test_values_are_converted_to_field_types():
    cfg = apply_overrides(
        _Cfg(), {"takt": "40.5", "reps": "3", "mode": "h-only", "spawn": "yes", "modes": "hrc", "cap": "2"}
    )
    assert cfg == _Cfg(takt=40.5, reps=3, mode="h-only", spawn=True, modes=("hrc",), cap=2.0)
    assert apply_overrides(cfg, {"cap": "none"}).cap is None


def test_unknown_key_lists_valid_keys():
    with pytest.raises(ConfigError) as info:
        apply_overrides(_Cfg(), {"tack": "1"})
    msg = str(info.value)
    assert "--set: unknown key 'tack'" in msg and "takt" in msg and "\n" not in msg


@pytest.mark.parametrize(
    ("key", "value", "expected"),
    [
        ("takt", "fast", "is not a number"),
        ("takt", "nan", "not a finite number"),
        ("reps", "2.5", "is not an integer"),
        ("mode", "solo", "is not one of hrc, h-only"),
        ("spawn", "maybe", "is not a boolean"),
        ("takt", "-1", "takt must be > 0 s"),
    ],
)
def test_bad_values_are_clear_errors(key, value, expected):
    with pytest.raises(ConfigError, match=expected):
        apply_overrides(_Cfg(), {key: value})


@pytest.mark.parametrize(("raw", "said"), [
    ("fast", "takt='fast' is not a number"),
    ("inf", "takt='inf' is not a finite number"),
    (True, "takt=True is not a number"),
    (None, "takt=None is not a number"),
])
def test_one_finite_float_parser_with_one_message_form(raw, said):
    assert finite_float("38", "takt", where="x") == 38.0 and finite_float(2, "takt", where="x") == 2.0
    with pytest.raises(ConfigError) as info:
        finite_float(raw, "takt", where="--set")
    assert str(info.value) == f"--set: {said}"
    with pytest.raises(TaskFileError, match="is not"):
        finite_float(raw, "takt", where="task.toml", error=TaskFileError)
