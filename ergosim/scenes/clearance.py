"""Clearance of a compiled workcell at its ``home`` keyframe: nothing starts inside furniture.

The file checks of :mod:`ergosim.scenes.cellfile` reason about boxes and points; this one asks MuJoCo for
the signed distance between real collision geoms (``mj_geomDistance``), so it also covers the robots' links
at their home poses, pedestals, meshes and socket blocks. It needs no simulation step. A robot link or
pedestal, or a part, more than :data:`PENETRATION` inside a piece of furniture is a ConfigError naming the
file, the entry and how deep.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.errors import ConfigError
from ergosim.robot.handle import robot_prefix
from ergosim.robot.robot_model import get_robot
from ergosim.scenes.cellspec import CellSpec

__all__ = ["PENETRATION", "check_clearance", "furniture_of_geoms"]

PENETRATION = 0.003
"""Largest penetration [m] tolerated at the home keyframe: resting contacts and a robot base standing on its
support touch (distance about 0); 3 mm is below any layout error that matters (assumed)."""

_PEDESTAL = "robot_pedestal"


def furniture_of_geoms(spec: CellSpec, model: mujoco.MjModel) -> dict[int, str]:
    """Geom id -> the furniture entry it belongs to (a table's slab and legs, a shelf's ledges and posts, a
    box and its stand are named after the entry); a robot's pedestal is ``robot_pedestal``."""
    names = [f.name for f in spec.furniture]
    out = {}
    for g in range(model.ngeom):
        if model.geom_bodyid[g] != 0:
            continue
        name = model.geom(g).name
        owner = next((n for n in names if name == n or name.startswith(f"{n}_")), None)
        if owner is not None:
            out[g] = owner
        elif name.split(".")[-1] == _PEDESTAL:  # a robot's pedestal (a second robot's is prefixed)
            out[g] = _PEDESTAL
    return out


def _solid(model: mujoco.MjModel, g: int) -> bool:
    return bool(model.geom_contype[g] or model.geom_conaffinity[g])


def _arm_geoms(model: mujoco.MjModel, base: str) -> list[int]:
    """The collision geoms of the robot whose base body is ``base`` (its subtree)."""
    root = model.body(base).id
    return [g for g in range(model.ngeom)
            if model.body_rootid[model.geom_bodyid[g]] == root and _solid(model, g)]


def check_clearance(spec: CellSpec, model: mujoco.MjModel, data: mujoco.MjData,
                    pose: str = "ready pose") -> None:
    """Raise ConfigError if, at the current state (``pose`` names the robots' posture in the message), a
    robot's links or pedestal or a part penetrate furniture by more than :data:`PENETRATION`, or two robots
    touch. A robot may touch its own support."""
    furniture = furniture_of_geoms(spec, model)
    fromto = np.zeros(6)

    def deepest(geoms, others, skip: set[str] = frozenset()) -> tuple[float, int, int]:
        worst = (0.0, -1, -1)
        for a in geoms:
            for b in others:
                if furniture.get(b) in skip:
                    continue
                d = mujoco.mj_geomDistance(model, data, a, b, PENETRATION, fromto)
                if d < worst[0]:
                    worst = (d, a, b)
        return worst

    arms = {r.name: _arm_geoms(model, robot_prefix(i, r.name) + get_robot(r.model).base)
            for i, r in enumerate(spec.robots)}
    for i, robot in enumerate(spec.robots):
        pedestal = [g for g, owner in furniture.items() if owner == _PEDESTAL
                    and model.geom(g).name == f"{robot_prefix(i, robot.name)}{_PEDESTAL}"]
        d, a, b = deepest(arms[robot.name] + pedestal, furniture, {robot.support, _PEDESTAL})
        if d < -PENETRATION:
            what = "its pedestal" if a in pedestal else model.body(model.geom_bodyid[a]).name
            raise ConfigError(f"the robot stands inside furniture {furniture[b]!r}: at its {pose} {what} "
                              f"is {-d * 1000:.0f} mm inside {model.geom(b).name}; move "
                              f"robots.{robot.name}.base or the furniture",
                              where=f"{spec.source}: robots.{robot.name}.base")
        for other in spec.robots[:i]:
            d, _, _ = deepest(arms[robot.name], arms[other.name])
            if d < -PENETRATION:
                raise ConfigError(f"robots {other.name!r} and {robot.name!r} intersect at their {pose}s "
                                  f"({-d * 1000:.0f} mm); move one of them",
                                  where=f"{spec.source}: robots.{robot.name}.base")
    for part in spec.parts:
        body = model.body(part.name).id
        geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == body and model.geom_contype[g]]
        d, _, b = deepest(geoms, furniture)
        if d < -PENETRATION:
            raise ConfigError(f"the part intersects furniture {furniture[b]!r}: it starts {-d * 1000:.0f} mm "
                              f"inside {model.geom(b).name}; move it (xy, on or pos)",
                              where=f"{spec.source}: parts.{part.name}")
