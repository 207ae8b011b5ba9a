"""One registry type serves every extension point (issue 25): a dict, register, names, get."""

from __future__ import annotations

import subprocess
import sys

import pytest

from ergosim.errors import ConfigError
from ergosim.experiment.scenario import SCENARIOS
from ergosim.registry import Registry
from ergosim.scenes.action_kinds import ACTION_KINDS
from ergosim.scenes.registry import SCENES
from ergosim.twin.modes import MODES, RISK_INDICES


def test_register_names_get_and_an_unknown_name_in_one_line():
    reg: Registry[int] = Registry("widget", where="--widget", hint="or a number")
    reg.register("a", 1)
    reg.register("b", 2)
    reg.register("a", 3)  # a later registration replaces an earlier one, in its place
    assert reg.names() == ("a", "b") and reg.get("a") == 3 and reg["b"] == 2 and "a" in reg and len(reg) == 2
    with pytest.raises(ConfigError) as info:
        reg.get("c")
    assert str(info.value) == "--widget: unknown widget 'c'; valid widgets: a, b (or a number)"
    with pytest.raises(KeyError):
        reg["c"]
    reg.unregister("a")
    reg.unregister("a")
    assert reg.names() == ("b",)


def test_every_extension_point_is_a_registry():
    assert all(isinstance(r, Registry) for r in (SCENARIOS, SCENES, MODES, RISK_INDICES, ACTION_KINDS))
    assert {"multi-subject", "kwear-validation", "gearbox"} <= set(SCENARIOS) and "gearbox" in SCENES
    assert MODES.names()[:4] == ("hrc", "rula", "h-only", "r-only")
    assert RISK_INDICES.names()[:2] == ("kwear", "rula-static")
    with pytest.raises(ConfigError, match="unknown risk index .x.; valid risk indices: kwear, rula-static"):
        RISK_INDICES.get("x")


def test_the_bundled_modes_are_a_catalogue_registered_on_first_use():
    """The mode registry's module imports no allocator: the bundled modes are ``ergosim.twin.catalogue``'s,
    imported when a registry is first read, and they come before a mode registered earlier than that."""
    code = ("import sys\n"
            "from ergosim.twin.modes import Mode, mode_names, register_mode, risk_index_names\n"
            "assert 'ergosim.twin.catalogue' not in sys.modules\n"
            "assert 'ergosim.twin.lookahead_allocator' not in sys.modules\n"
            "register_mode(Mode('mine', 'a mode of my own'))\n"
            "print(','.join(mode_names()), ','.join(risk_index_names()))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["hrc,rula,h-only,r-only,hrc-reba,reba,kwear-lookahead,mine",
                           "kwear,rula-static,kwear-reba,reba-static"]
