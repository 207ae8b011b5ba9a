"""Layout as data: the frozen configuration every workcell is built from.

Lengths in metres, angles in degrees, world frame: x forward from the worker, y to the worker's left,
z up, floor at z = 0. A scene subclasses :class:`WorkcellConfig` with its own furniture; a user overrides
any field by name with :func:`with_overrides` (``{"shelf_height": 1.9}``). Moving furniture or parts
changes only geometry: the worker's postures, and so the ergonomics, follow from it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, Literal

from ergosim.errors import ConfigError
from ergosim.overrides import apply_overrides
from ergosim.scenes.parts import PROFILES, PartDims

__all__ = ["Hollow", "Surface", "WorkcellConfig", "with_overrides"]

Hollow = Literal["x", "y", "z"]


@dataclasses.dataclass(frozen=True)
class Surface:
    """A horizontal support: centre (x, y) [m], size (along x, along y) [m], top height [m]."""

    name: str
    center: tuple[float, float]
    size: tuple[float, float]
    height: float

    def contains(self, xy: tuple[float, float], margin: float = 0.0) -> bool:
        return all(abs(xy[i] - self.center[i]) <= self.size[i] / 2 - margin for i in range(2))


@dataclasses.dataclass(frozen=True)
class WorkcellConfig:
    """Fields shared by every workcell. Part placements are (x, y) on a named surface plus a yaw [deg];
    J's yaw turns its hollows (J's +x and +y hollows point forward-right and forward-left at -45 deg)."""

    timestep: float = 0.002
    """Physics step [s]."""
    stature: float = 1.75
    """Worker stature [m] (scales the human model)."""
    human_scale: tuple[tuple[str, float], ...] = ()
    """Per-segment length multipliers of the worker, (segment, factor) pairs (a synthetic subject's
    ``Subject.scale``); empty = the population proportions for ``stature``."""
    worker_xy: tuple[float, float] = (0.0, 0.0)
    """Pelvis position on the floor [m]; the worker faces +x rotated by ``worker_yaw``."""
    worker_yaw: float = 0.0
    robot_base: tuple[float, float, float] = (0.78, -0.42, 0.9)
    """Position of ``panda_link0`` [m]."""
    robot_yaw: float = 180.0
    """Yaw of the robot base [deg]; 180 faces the worker."""
    bench_center: tuple[float, float] = (0.62, 0.0)
    bench_size: tuple[float, float] = (0.64, 1.4)
    bench_height: float = 0.9
    profile_width: float = 0.03
    s_length: float = 0.30
    """Length of S1 and S2 [m]."""
    l_length: float = 0.20
    """Length of L [m] (shorter than S1, S2)."""
    hollow_L: Hollow = "x"
    hollow_S1: Hollow = "z"
    hollow_S2: Hollow = "y"
    seat_tolerance: float = 0.006
    """A profile within this distance [m] of its seated pose is seated (welded to J)."""
    seat_tolerance_deg: float = 8.0
    carry_height: float = 0.0
    """Lowest height [m] of the robot's TCP when carrying a part between pick and place (clears what stands
    on the bench, e.g. a profile upright in J)."""
    grasp_tolerance: float = 0.02
    """A held part farther than this [m] from where it was grasped counts as dropped."""

    # -- derived ------------------------------------------------------------------------------------------
    @property
    def dims(self) -> PartDims:
        return PartDims(profile_width=self.profile_width, s_length=self.s_length, l_length=self.l_length)

    def hollow(self, profile: str) -> Hollow:
        return getattr(self, f"hollow_{profile}")

    def surfaces(self) -> dict[str, Surface]:
        return {"bench": Surface("bench", self.bench_center, self.bench_size, self.bench_height)}

    def placements(self) -> dict[str, tuple[str, tuple[float, float], float]]:
        """part -> (surface name, (x, y) [m], yaw [deg]) of its initial pose (scenes override)."""
        return {}

    # -- validation ---------------------------------------------------------------------------------------
    def validate(self, where: str = "scene config") -> None:
        def need(ok: bool, msg: str) -> None:
            if not ok:
                raise ConfigError(msg, where=where)

        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            vals = v if isinstance(v, tuple) else (v,)
            need(all(not isinstance(x, float) or math.isfinite(x) for x in vals),
                 f"{f.name}={v} is not finite")
        need(0.0005 <= self.timestep <= 0.01, f"timestep must be in [0.0005, 0.01] s, got {self.timestep}")
        need(1.4 <= self.stature <= 2.1, f"stature must be in [1.4, 2.1] m, got {self.stature}")
        need(0.01 <= self.profile_width <= 0.06,
             f"profile_width must be in [0.01, 0.06] m, got {self.profile_width}")
        need(0.05 <= self.l_length < self.s_length <= 1.0,
             f"need 0.05 <= l_length < s_length <= 1 m, got L={self.l_length}, S={self.s_length}")
        hollows = {self.hollow(p) for p in PROFILES}
        need(hollows == {"x", "y", "z"}, f"hollow_L/S1/S2 must use each hollow x, y, z once, got {hollows}")
        need(self.seat_tolerance > 0 and self.seat_tolerance_deg > 0, "seat tolerances must be > 0")
        surfaces = self.surfaces()
        for s in surfaces.values():
            need(all(x > 0 for x in s.size), f"{s.name} size must be > 0, got {s.size}")
            need(0.3 <= s.height <= 2.2, f"{s.name} height must be in [0.3, 2.2] m, got {s.height}")
        for part, (surface, xy, _) in self.placements().items():
            need(surface in surfaces,
                 f"{part} is on unknown surface {surface!r}; surfaces: {', '.join(surfaces)}")
            need(surfaces[surface].contains(xy, margin=0.02),
                 f"{part} at {xy} is not on the {surface} (centre {surfaces[surface].center}, "
                 f"size {surfaces[surface].size})")


def with_overrides(cfg: Any, overrides: Mapping[str, Any], where: str = "scene config") -> Any:
    """A copy of ``cfg`` with fields replaced by name; strings are converted to the field's type
    (``"1.9"``, ``"0.7,-0.6"``). Unknown keys or bad values raise :class:`ConfigError`."""
    try:
        return apply_overrides(cfg, dict(overrides), where=where)
    except (TypeError, ValueError) as err:
        raise ConfigError(str(err), where=where) from None
