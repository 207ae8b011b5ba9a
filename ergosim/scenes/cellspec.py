"""A workcell as data: furniture, parts, slots, targets, the worker, robots, actions and camera views.

This is the parsed form of a workcell file (docs/workcell_format.md). Lengths in metres, angles in degrees,
masses in kilograms, world frame: x forward from the worker, y to the worker's left, z up, floor at z = 0.
Every entity is a small frozen dataclass; :class:`CellSpec` holds them in file order (the build order).
Parsing and every check that needs no physics live in :mod:`ergosim.scenes.cellfile`.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

from ergosim.errors import ConfigError
from ergosim.robot.ssm import SSMParams
from ergosim.scenes.action_kinds import ACTION_KINDS
from ergosim.scenes.surface import Surface, turned

__all__ = ["Surface", "Table", "Shelf", "Box", "Slot", "Part", "Target", "Worker", "Robot", "Action", "View",
           "CellSpec", "ACTION_KINDS", "SHAPES", "Furniture", "SHELF_BACKS"]

SHAPES = ("box", "cylinder", "mesh", "socket_block")
SHELF_BACKS = ("-y", "+y", "-x", "+x")
"""The sides of its own frame a shelf's top ledge may stand against (``back``)."""


@dataclasses.dataclass(frozen=True)
class Table:
    """A slab whose top is at ``height`` on four legs (or none), turned by ``yaw`` [deg] about its centre:
    one surface named after it."""

    name: str
    center: tuple[float, float]
    size: tuple[float, float]
    height: float
    thickness: float = 0.04
    legs: bool = True
    rgba: tuple[float, ...] = (0.72, 0.6, 0.45, 1.0)
    yaw: float = 0.0

    def surfaces(self) -> list[Surface]:
        return [Surface(self.name, self.center, self.size, self.height, self.yaw)]

    def boxes(self) -> list[tuple[np.ndarray, np.ndarray, float]]:
        """(centre (3,) [m], half sizes (3,) [m] along the box's own axes, yaw [deg] about z) of every solid
        box, for overlap checks, the standing area and the worker's obstacles."""
        (cx, cy), (sx, sy), h, t = self.center, self.size, self.height, self.thickness
        return [(np.array([cx, cy, h - t / 2]), np.array([sx / 2, sy / 2, t / 2]), self.yaw)]


@dataclasses.dataclass(frozen=True)
class Shelf:
    """A stepped shelf: a full lower ledge at ``low_height`` on legs, and a top ledge at ``height`` covering
    only ``top_depth`` [m] of the footprint from its ``back`` side (-y, +y, -x or +x of its own frame), on
    four posts; the whole turned by ``yaw`` [deg] about ``center``. Surfaces ``<name>_top``,
    ``<name>_low``."""

    name: str
    center: tuple[float, float]
    size: tuple[float, float]
    height: float
    low_height: float
    top_depth: float
    thickness: float = 0.03
    rgba: tuple[float, ...] = (0.72, 0.6, 0.45, 1.0)
    yaw: float = 0.0
    back: Literal["-y", "+y", "-x", "+x"] = "-y"

    @property
    def depth(self) -> float:
        """The footprint's extent [m] across the back side (along y for a -y or +y back, else along x)."""
        return self.size[1] if self.back[1] == "y" else self.size[0]

    def ledges(self) -> tuple[Surface, Surface]:
        (cx, cy), (sx, sy), d = self.center, self.size, self.top_depth
        low = Surface(f"{self.name}_low", (cx, cy), (sx, sy), self.low_height, self.yaw)
        sign = -1.0 if self.back[0] == "-" else 1.0
        if self.back[1] == "y":
            offset, size = (0.0, sign * (sy / 2 - d / 2)), (sx, d)
        else:
            offset, size = (sign * (sx / 2 - d / 2), 0.0), (d, sy)
        if self.back == "-y" and self.yaw == 0.0:
            centre = (cx, cy - sy / 2 + d / 2)  # the arithmetic of the original -y ledge, bit for bit
        else:
            centre = turned(self.center, offset, self.yaw)
        top = Surface(f"{self.name}_top", centre, size, self.height, self.yaw)
        return top, low

    def surfaces(self) -> list[Surface]:
        return list(self.ledges())

    def boxes(self) -> list[tuple[np.ndarray, np.ndarray, float]]:
        t = self.thickness
        return [(np.array([*s.center, s.height - t / 2]), np.array([s.size[0] / 2, s.size[1] / 2, t / 2]),
                 self.yaw) for s in self.ledges()]


@dataclasses.dataclass(frozen=True)
class Box:
    """A solid box: centre (x, y, z) and half sizes [m], whose top is a surface named after it; optionally
    on a post (``stand_half`` (x, y) half sizes, offset ``stand_offset`` (x, y) from the centre) down to
    surface ``stand_to`` (a monitor); turned by ``yaw`` [deg] about its centre (the post with it)."""

    name: str
    center: tuple[float, float, float]
    half: tuple[float, float, float]
    rgba: tuple[float, ...] = (0.45, 0.47, 0.5, 1.0)
    stand_to: str | None = None
    stand_offset: tuple[float, float] = (0.0, 0.0)
    stand_half: tuple[float, float] = (0.015, 0.04)
    yaw: float = 0.0

    def surfaces(self) -> list[Surface]:
        """Its top face, named after it (a riser on a bench holds parts)."""
        (x, y, z), (hx, hy, hz) = self.center, self.half
        return [Surface(self.name, (x, y), (2 * hx, 2 * hy), z + hz, self.yaw)]

    def boxes(self) -> list[tuple[np.ndarray, np.ndarray, float]]:
        return [(np.array(self.center, dtype=float), np.array(self.half, dtype=float), self.yaw)]


Furniture = Table | Shelf | Box


@dataclasses.dataclass(frozen=True)
class Slot:
    """Where another part is inserted into ``host``: ``at`` (3,) the point in the host's frame [m] where the
    inserted part's inner end comes to rest, ``axis`` (3,) the unit direction (host frame) the inserted part
    sticks out along. The inserted part's own insertion axis (``Part.insert_axis``) is laid along ``axis``."""

    host: str
    name: str
    at: tuple[float, float, float]
    axis: tuple[float, float, float]

    @property
    def key(self) -> str:
        return f"{self.host}.{self.name}"


COUPLINGS = ("good", "fair", "poor", "unacceptable")
"""REBA's coupling levels a part's ``coupling`` may name (Hignett & McAtamney 2000)."""


@dataclasses.dataclass(frozen=True)
class Part:
    """A free body. ``shape``: box (``size`` full (x, y, z) [m]), cylinder (``radius``, ``length`` along local
    z), mesh (``file`` STL, ``scale``; its bounding box stands in for size), socket_block (a core cube with
    square sleeves along ``sleeves``, each taking a profile of width ``bore``).

    Mass: ``mass`` [kg], else ``density`` [kg/m^3] × (``section_area`` [m^2] × length along x, for an
    extrusion; else the solid volume). Placement: resting on surface ``on`` ("auto": the highest surface
    under ``xy``) at ``xy`` with ``yaw`` [deg], or at a full pose ``pos`` (3,) [m] + ``rpy`` [deg].
    ``insert_axis``: the local axis that goes along a slot's axis when the part is inserted. ``grasp``:
    where a robot takes it from above, at its middle or just below its top (a screw by its head).
    """

    name: str
    shape: Literal["box", "cylinder", "mesh", "socket_block"]
    size: tuple[float, ...] = ()
    radius: float = 0.0
    length: float = 0.0
    file: str | None = None
    scale: float = 1.0
    bore: float = 0.03
    clearance: float = 0.0005
    wall: float = 0.003
    sleeve_length: float = 0.03
    sleeves: tuple[str, ...] = ("x", "y", "z")
    mass: float | None = None
    density: float | None = None
    section_area: float | None = None
    rgba: tuple[float, ...] = (0.62, 0.66, 0.72, 1.0)
    on: str | None = "auto"
    xy: tuple[float, float] | None = None
    yaw: float = 0.0
    pos: tuple[float, float, float] | None = None
    rpy: tuple[float, float, float] | None = None
    insert_axis: Literal["x", "y", "z"] = "x"
    grasp: Literal["center", "top"] = "center"
    slots: tuple[Slot, ...] = ()
    coupling: str | None = None
    """How the worker's hand holds it, one of :data:`COUPLINGS` (REBA's coupling); None: from its grip width
    (:func:`ergosim.ergonomics.reba_parts.grip_coupling`, applied where the worker is scored)."""

    @property
    def core_half(self) -> float:
        """socket_block: half edge of the core cube = outer half width of a sleeve [m]."""
        return self.bore / 2 + self.clearance + self.wall

    @property
    def half_extents(self) -> tuple[float, float, float]:
        """Half extents (x, y, z) of the part's bounding box in its own frame [m] (socket_block: the core)."""
        if self.shape in ("box", "mesh"):
            return (self.size[0] / 2, self.size[1] / 2, self.size[2] / 2)
        if self.shape == "cylinder":
            return (self.radius, self.radius, self.length / 2)
        c = self.core_half
        return (c, c, c)

    @property
    def insert_half_length(self) -> float:
        """Half extent along ``insert_axis`` [m]: the seated origin lies this far out of the slot's point."""
        return self.half_extents["xyz".index(self.insert_axis)]

    @property
    def grip_width(self) -> float:
        """Width across a top-down grasp (the fingers close along the part's local y) [m]."""
        if self.shape == "socket_block":
            return 2 * self.core_half
        if self.shape == "cylinder":
            return 2 * self.radius
        return self.size[1]

    def rest_height(self) -> float:
        """Height [m] of the part's frame above the surface it rests on (resting with its local z up; a
        socket_block rests on its core with the +z sleeve up)."""
        if self.shape == "socket_block":
            return self.core_half
        return self.half_extents[2]

    def total_mass(self) -> float | None:
        """[kg], or None when MuJoCo derives it from the geoms' density."""
        if self.mass is not None:
            return self.mass
        if self.density is not None and self.section_area is not None:
            return self.density * self.section_area * self.size[0]
        return None


@dataclasses.dataclass(frozen=True)
class Target:
    """A named place. ``kind`` place: on surface ``on`` at ``xy`` [m], ``yaw`` [deg], at the height where
    ``part``'s frame rests there; free (handover poses, fixtures in the air): at ``pos`` (3,) [m]."""

    name: str
    kind: Literal["place", "free"]
    on: str | None = None
    xy: tuple[float, float] | None = None
    yaw: float = 0.0
    part: str | None = None
    pos: tuple[float, float, float] | None = None


@dataclasses.dataclass(frozen=True)
class Worker:
    """The worker's pelvis on the floor at ``xy`` [m], facing +x turned by ``yaw`` [deg]; ``hand``: the
    dominant (acting) hand; ``stature`` [m] and ``human_scale`` ((segment, factor) pairs) build the body;
    ``name``: the task's human agent this body is. ``standing_area`` (x_min, x_max, y_min, y_max) [m] in
    the worker's frame bounds where the pelvis may step (None: the clear floor within one step,
    :mod:`ergosim.worker.stance`; all zeros: the feet stay planted); ``max_turn`` [deg] how far the worker
    may turn on the spot (None: 90 deg)."""

    name: str = "human"
    xy: tuple[float, float] = (0.0, 0.0)
    yaw: float = 0.0
    hand: Literal["right", "left"] = "right"
    stature: float = 1.75
    human_scale: tuple[tuple[str, float], ...] = ()
    standing_area: tuple[float, float, float, float] | None = None
    max_turn: float | None = None


@dataclasses.dataclass(frozen=True)
class Robot:
    """A robot named like its task agent: ``model`` a registered robot model
    (:func:`ergosim.robot.robot_names`; a file that names none gets :func:`ergosim.robot.default_robot`),
    its base body at ``base`` (3,) [m] turned by ``yaw`` [deg]; a pedestal fills the gap down to surface
    ``support``. ``park_clearance`` [m]: the distance its park (home) pose keeps from the worker's head,
    neck and chest (:mod:`ergosim.scenes.park`; 0: the model's ready pose as it is)."""

    name: str
    model: str
    base: tuple[float, float, float] = (0.0, 0.0, 0.0)
    yaw: float = 0.0
    support: str | None = None
    park_clearance: float = 0.5


@dataclasses.dataclass(frozen=True)
class Action:
    """The physical action of a task label. ``kind``: one of :data:`ACTION_KINDS`
    (:mod:`ergosim.scenes.action_kinds`); ``target``: a place target (place, remove), a slot key
    ``host.slot`` (insert, fasten) or a free target (handover); ``handover``: a free target where a robot
    doing the action hands the part to the worker, who finishes it; ``turn_time`` [s]: how long a fastener
    is held and turned."""

    label: str
    kind: str
    part: str
    target: str
    handover: str | None = None
    turn_time: float = 0.0


@dataclasses.dataclass(frozen=True)
class View:
    """A free camera: ``azimuth``, ``elevation`` [deg], ``distance`` [m], ``lookat`` (3,) [m]."""

    name: str
    azimuth: float
    elevation: float
    distance: float = 2.6
    lookat: tuple[float, float, float] = (0.35, 0.0, 1.0)


@dataclasses.dataclass(frozen=True)
class CellSpec:
    """A whole workcell. ``source`` names the file (or ``<inline>``) in messages."""

    name: str
    source: str
    furniture: tuple[Furniture, ...]
    parts: tuple[Part, ...]
    targets: tuple[Target, ...]
    actions: tuple[Action, ...]
    worker: Worker
    robots: tuple[Robot, ...]
    views: tuple[View, ...]
    timestep: float = 0.002
    seat_tolerance: float = 0.006
    seat_tolerance_deg: float = 8.0
    place_tolerance: float = 0.03
    carry_height: float = 0.0
    grasp_tolerance: float = 0.02
    description: str = ""
    safety: SSMParams = SSMParams()
    """Speed and separation monitoring of the shared space (the ``[safety]`` table)."""

    def surfaces(self) -> dict[str, Surface]:
        return {s.name: s for f in self.furniture for s in f.surfaces()}

    def part(self, name: str) -> Part:
        return next(p for p in self.parts if p.name == name)

    def slots(self) -> dict[str, Slot]:
        return {s.key: s for p in self.parts for s in p.slots}

    def action(self, label: str) -> Action:
        return next(a for a in self.actions if a.label == label)

    def surface_under(self, xy) -> Surface | None:
        """The highest surface whose footprint contains ``xy``."""
        under = [s for s in self.surfaces().values() if s.contains(xy)]
        return max(under, key=lambda s: s.height) if under else None

    def view(self, name: str | None = None) -> View:
        """The camera view ``name`` (the first one for None); an unknown name is a :class:`ConfigError`
        that lists the cell's views."""
        if name is None:
            return self.views[0]
        for v in self.views:
            if v.name == name:
                return v
        raise ConfigError(f"unknown view {name!r}; the workcell {self.name!r} has: "
                          f"{', '.join(v.name for v in self.views)}", where=f"{self.source}: [views]")
