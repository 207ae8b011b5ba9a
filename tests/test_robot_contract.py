"""The robot contract: the registry, what a robot cannot do (gripper, payload, reach) in words, and no
Panda-specific name outside ergosim/robot/panda* (the Panda's module) and models/panda (its data)."""

from __future__ import annotations

from pathlib import Path

import pytest

from ergosim.errors import ConfigError
from ergosim.robot import PANDA, UR5, get_robot, robot_names
from ergosim.robot.capability import refusal

ROOT = Path(__file__).resolve().parents[1]


def test_registry():
    assert get_robot("panda") is PANDA and get_robot("ur5") is UR5
    assert {"panda", "ur5"} <= set(robot_names())
    with pytest.raises(ConfigError, match="unknown robot model 'kuka'; models: panda, ur5"):
        get_robot("kuka")


def test_refusals_name_the_limit():
    assert refusal(UR5, "g2", "bushing", 0.047, 0.3) is None
    assert refusal(UR5, "g4", "gear", 0.060, 0.4) == ("ur5 cannot do g4: gear is 60 mm wide and the gripper "
                                                     "opens 55 mm")
    assert refusal(PANDA, "g4", "gear", 0.060, 0.4) is None
    assert refusal(PANDA, "a1", "block", 0.05, 3.5) == ("panda cannot do a1: it carries 3.50 kg (block) and "
                                                       "its payload is 3 kg")
    assert refusal(UR5, "a1", "block", 0.05, 3.5) is None
    assert "out of its reach" in refusal(PANDA, "a5", "J", 0.03, 0.2, reachable=False)
