"""Clearance of a compiled workcell at its ``home`` keyframe: nothing starts inside furniture.

The file checks of :mod:`ergosim.scenes.cellfile` reason about boxes and points; this one asks MuJoCo for
the signed distance between real collision geoms (``mj_geomDistance``), so it also covers the Panda's links
at its ready pose, pedestals, meshes and socket blocks. It needs no simulation step. A robot link or
pedestal, or a part, more than :data:`PENETRATION` inside a piece of furniture is a ConfigError naming the
file, the entry and how deep.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.errors import ConfigError
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
        elif name == _PEDESTAL:
            out[g] = _PEDESTAL
    return out


def _solid(model: mujoco.MjModel, g: int) -> bool:
    return bool(model.geom_contype[g] or model.geom_conaffinity[g])


def check_clearance(spec: CellSpec, model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Raise ConfigError if, at the current state (the home keyframe), a robot's links or pedestal or a part
    penetrate furniture by more than :data:`PENETRATION`. The robot's support may be touched."""
    furniture = furniture_of_geoms(spec, model)
    support = {r.support for r in spec.robots}
    fromto = np.zeros(6)

    def deepest(geoms, skip: set[str]) -> tuple[float, int, int]:
        worst = (0.0, -1, -1)
        for a in geoms:
            for b, owner in furniture.items():
                if owner in skip:
                    continue
                d = mujoco.mj_geomDistance(model, data, a, b, PENETRATION, fromto)
                if d < worst[0]:
                    worst = (d, a, b)
        return worst

    if spec.robots:
        root = model.body("panda_link0").id
        arm = [g for g in range(model.ngeom)
               if model.body_rootid[model.geom_bodyid[g]] == root and _solid(model, g)]
        pedestal = [g for g in range(model.ngeom) if model.geom(g).name == _PEDESTAL]
        robot = spec.robots[0]
        d, a, b = deepest(arm + pedestal, support | {_PEDESTAL})
        if d < -PENETRATION:
            what = "its pedestal" if a in pedestal else model.body(model.geom_bodyid[a]).name
            raise ConfigError(f"the robot stands inside furniture {furniture[b]!r}: at its ready pose {what} "
                              f"is {-d * 1000:.0f} mm inside {model.geom(b).name}; move "
                              f"robots.{robot.name}.base or the furniture",
                              where=f"{spec.source}: robots.{robot.name}.base")
    for part in spec.parts:
        body = model.body(part.name).id
        geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == body and model.geom_contype[g]]
        d, _, b = deepest(geoms, set())
        if d < -PENETRATION:
            raise ConfigError(f"the part intersects furniture {furniture[b]!r}: it starts {-d * 1000:.0f} mm "
                              f"inside {model.geom(b).name}; move it (xy, on or pos)",
                              where=f"{spec.source}: parts.{part.name}")
