"""Workcell files (TOML): read, override by dotted path, and check everything that needs no physics.

The format is documented field by field in docs/workcell_format.md. A file is parsed to a plain dict,
overrides are applied to that dict (``parts.L.xy = "0.2,0.8"``, or a legacy alias such as ``l_xy`` declared
in the file's ``[aliases]`` table), then :func:`parse_cell` builds the frozen :class:`CellSpec` and checks
names, ranges and geometry: unknown parts, surfaces or slots, overlapping furniture, a robot base inside
furniture, parts intersecting furniture or floating. Every problem is one :class:`ConfigError` naming the
file, the entry and what was expected.
"""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ergosim.errors import ConfigError
from ergosim.human.anthropometry import SEGMENT_SCALES
from ergosim.quat import from_rpy, to_mat
from ergosim.robot.robot_model import default_robot, robot_names
from ergosim.robot.ssm import SSMParams
from ergosim.scenes.cell_schema import (
    CELL,
    FURNITURE,
    TABLES,
    ActionTable,
    PartTable,
    RobotTable,
    SafetyTable,
    SlotTable,
    TargetTable,
    TopTable,
    ViewTable,
    WorkerTable,
)
from ergosim.scenes.cellspec import (
    ACTION_KINDS,
    COUPLINGS,
    SHAPES,
    Action,
    Box,
    CellSpec,
    Part,
    Robot,
    Shelf,
    Slot,
    Table,
    Target,
    View,
    Worker,
)
from ergosim.schema.document import check_table, override, paths
from ergosim.schema.values import AXES

__all__ = ["read_cell_file", "parse_cell", "apply_cell_overrides", "override_paths", "cell_keys",
           "MAX_FILE_BYTES", "TURN_TIME_MAX", "MAX_PART_MASS", "MAX_DENSITY", "MAX_MESH_TRIANGLES"]

MAX_FILE_BYTES = 4 * 1024 * 1024
"""Largest workcell or scenario file read [bytes]; a cell is a few kB."""

TURN_TIME_MAX = 600.0
"""Longest hold-and-turn of a fastening [s] (assumed: ten minutes is no longer one action; the worker's motion
holds a pose per mocap frame of it)."""
MAX_PART_MASS = 100.0
"""Heaviest part [kg] (assumed: four times the load constant of the NIOSH lifting equation, 23 kg (Waters et
al. 1993), far beyond what is carried by hand in an assembly cell; 1e30 kg made the physics diverge)."""
MAX_DENSITY = 22_590.0
"""Densest part material [kg/m^3]: osmium, the densest element (CRC Handbook of Chemistry and Physics)."""
MAX_MESH_TRIANGLES = 50_000
"""Most triangles of a part's STL mesh (assumed: the bundled robot meshes have at most 1,176; a 199,000-
triangle STL, under MuJoCo's cap of 200,000, kept the build busy past 240 s)."""


def read_cell_file(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The TOML document at ``path`` (a regular file of at most :data:`MAX_FILE_BYTES`)."""
    return read_toml(path, what="workcell file")


def read_toml(path: str | os.PathLike[str], what: str) -> dict[str, Any]:
    p = Path(path)
    if not p.exists():
        raise ConfigError(f"no such {what}", where=str(path))
    if not p.is_file():
        raise ConfigError(f"not a regular file; a {what} must be a TOML file", where=str(path))
    if p.stat().st_size > MAX_FILE_BYTES:
        raise ConfigError(f"larger than {MAX_FILE_BYTES // 1024 // 1024} MiB; not a {what}", where=str(path))
    try:
        return tomllib.loads(p.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"invalid TOML: {err}", where=str(path)) from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise ConfigError(f"nested too deeply to be a {what} (arrays or inline tables inside each other "
                          "hundreds of levels deep)", where=str(path)) from None
    except (OSError, UnicodeDecodeError) as err:
        raise ConfigError(f"cannot read the {what}: {err}", where=str(path)) from None


# -- overrides -------------------------------------------------------------------------------------------
def cell_keys(doc: Mapping[str, Any]) -> list[str]:
    """Every settable dotted path of ``doc`` (existing entries' fields) plus its aliases."""
    return paths(CELL, doc) + sorted(doc.get("aliases") or {})


def apply_cell_overrides(doc: Mapping[str, Any], overrides: Mapping[str, Any], where: str) -> dict[str, Any]:
    """A deep copy of the cell document ``doc`` with ``overrides`` (dotted path or alias -> value) set.

    A string (``"0.2,0.8"``) is converted by its field's kind (:mod:`ergosim.scenes.cell_schema`), a value
    already typed is set as it is; both are checked when the cell is parsed. An alias may stand for several
    paths (``assembly_yaw`` turns both targets that use it)."""
    out = dict(doc)
    aliases = out.get("aliases") or {}

    def unknown(key: str, valid: list[str]) -> str:
        sample = ", ".join(sorted(aliases) or valid[:12])
        return f"unknown key {key!r}; valid keys include: {sample} (or a dotted path such as parts.<name>.xy)"

    for key, value in overrides.items():
        for path in override_paths(out, key):
            out = override(CELL, out, {path: value}, where, said=lambda _p, k=key: k,
                           unknown=lambda _p, valid, k=key: unknown(k, valid))
            section, last = path.split(".")[0], path.split(".")[-1]
            for other in _EXCLUSIVE.get((section, last), ()):
                _node(out, path).pop(other, None)  # a full pose replaces a resting placement, and vice versa
    return out


def _node(doc: dict, path: str) -> dict:
    """The table holding the field at ``path`` (a slot is named by its name in its array)."""
    *head, _ = path.split(".")
    node = doc
    for i, k in enumerate(head):
        node = next(s for s in node if s.get("name") == k) if isinstance(node, list) else node[k]
    return node


def override_paths(doc: Mapping[str, Any], key: str) -> list[str]:
    """The dotted paths of ``doc`` that the override ``key`` sets: ``key`` itself, or what its alias stands
    for (the file's ``[aliases]``)."""
    named = (doc.get("aliases") or {}).get(key, key)
    return [named] if isinstance(named, str) else list(named)


_EXCLUSIVE = {("parts", "pos"): ("xy", "on"), ("parts", "xy"): ("pos", "rpy"),
              ("parts", "on"): ("pos", "rpy"), ("targets", "pos"): ("xy", "on", "part")}
"""Setting the first field of a placement by override drops the fields of the other kind of placement."""


# -- parsing ---------------------------------------------------------------------------------------------
def parse_cell(doc: Mapping[str, Any], source: str = "<inline>") -> CellSpec:
    """Build and check the :class:`CellSpec` of the workcell document ``doc``; ``source`` names it."""
    top = {k: v for k, v in doc.items() if k not in TABLES}
    fields = check_table(TopTable, top, source, required=("name",))
    for t in TABLES:
        if t in doc and not isinstance(doc[t], dict):
            raise ConfigError(f"expected a table, got {doc[t]!r}", where=f"{source}: {t}")
    at = lambda entry: f"{source}: {entry}"  # noqa: E731
    for alias, named in doc.get("aliases", {}).items():
        if not (isinstance(named, str) or isinstance(named, list) and named
                and all(isinstance(s, str) for s in named)):
            raise ConfigError(f"an alias stands for a dotted path or a list of them, got {named!r}",
                              where=at(f"aliases.{alias}"))
    worker = Worker(**check_table(WorkerTable, doc.get("worker", {}), at("worker")))
    furniture = tuple(_furniture(name, t, at(f"furniture.{name}"))
                      for name, t in doc.get("furniture", {}).items())
    parts = tuple(_part(name, t, at(f"parts.{name}")) for name, t in doc.get("parts", {}).items())
    targets = tuple(_target(name, t, at(f"targets.{name}")) for name, t in doc.get("targets", {}).items())
    robots = tuple(Robot(name=name, **{"model": default_robot(),
                                       **check_table(RobotTable, t, at(f"robots.{name}"),
                                                     required=("base",))})
                   for name, t in doc.get("robots", {}).items())
    actions = tuple(Action(label=name, **check_table(ActionTable, t, at(f"actions.{name}"),
                                                 required=("kind", "part", "target")))
                    for name, t in doc.get("actions", {}).items())
    views = tuple(View(name=name, **check_table(ViewTable, t, at(f"views.{name}"),
                                                required=("azimuth", "elevation")))
                  for name, t in doc.get("views", {}).items())
    if not views:
        views = (View("default", 215.0, -28.0),)
    safety = SSMParams(**check_table(SafetyTable, doc.get("safety", {}), at("safety")))
    safety.validate(at("safety"))
    spec = CellSpec(furniture=furniture, parts=parts, targets=targets, actions=actions, worker=worker,
                    robots=robots, views=views, source=source, safety=safety, **fields)
    _check(spec, at)
    return spec


def _furniture(name: str, t: Any, where: str):
    if not isinstance(t, dict):
        raise ConfigError(f"expected a table, got {t!r}", where=where)
    kind = t.get("type", "table")
    if kind not in FURNITURE:
        raise ConfigError(f"unknown furniture type {kind!r}; types: {', '.join(FURNITURE)}", where=where)
    required = {"table": ("center", "size", "height"), "shelf": ("center", "size", "height", "low_height",
                                                                 "top_depth"),
                "box": ("center", "half")}[kind]
    f = check_table(FURNITURE[kind], t, where, required)
    f.pop("type", None)
    return {"table": Table, "shelf": Shelf, "box": Box}[kind](name=name, **f)


def _part(name: str, t: Any, where: str) -> Part:
    f = check_table(PartTable, t, where, required=("shape",))
    if f["shape"] not in SHAPES:
        raise ConfigError(f"unknown shape {f['shape']!r}; shapes: {', '.join(SHAPES)}",
                          where=f"{where}.shape")
    need = {"box": ("size",), "cylinder": ("radius", "length"), "mesh": ("file", "size"), "socket_block": ()}
    for k in need[f["shape"]]:
        if k not in f:
            raise ConfigError(f"a {f['shape']} needs {k!r}", where=where)
    if f.get("grasp", "center") not in ("center", "top"):
        raise ConfigError(f"expected center or top, got {f['grasp']!r}", where=f"{where}.grasp")
    if f.get("coupling", "good") not in COUPLINGS:
        raise ConfigError(f"coupling must be one of {', '.join(COUPLINGS)} (REBA's), got {f['coupling']!r}",
                          where=f"{where}.coupling")
    if f.get("insert_axis", "x") not in ("x", "y", "z"):
        raise ConfigError(f"expected x, y or z, got {f['insert_axis']!r}", where=f"{where}.insert_axis")
    for s in f.get("sleeves", ()):
        if s not in ("x", "y", "z"):
            raise ConfigError(f"sleeves are among x, y, z, got {s!r}", where=f"{where}.sleeves")
    slots = []
    raw_slots = f.pop("slots", [])
    if not isinstance(raw_slots, list):
        raise ConfigError("expected an array of tables [[parts.NAME.slots]]", where=f"{where}.slots")
    for i, s in enumerate(raw_slots):
        sf = check_table(SlotTable, s, f"{where}.slots[{i}]", required=("name", "at", "axis"))
        slots.append(Slot(host=name, **sf))
    part = Part(name=name, **f)
    if part.shape == "socket_block":
        c = part.core_half
        for axis in part.sleeves:
            unit = AXES[axis]
            slots.append(Slot(name, axis, tuple(c * u for u in unit), unit))
    names = [s.name for s in slots]
    if len(set(names)) != len(names):
        raise ConfigError(f"duplicate slot names {names}", where=f"{where}.slots")
    for i, a in enumerate(slots):
        for b in slots[i + 1:]:
            if math.dist(a.at, b.at) < _SLOT_GAP:
                raise ConfigError(f"slots {a.name!r} and {b.name!r} overlap: their seats are "
                                  f"{math.dist(a.at, b.at) * 1000:.1f} mm apart (at least "
                                  f"{_SLOT_GAP * 1000:.0f} mm)", where=f"{where}.slots")
    part = Part(**{**part.__dict__, "slots": tuple(slots)})
    positive = {"cylinder": ("radius", "length"), "mesh": ("scale",), "socket_block": ("bore", "wall",
                                                                                 "sleeve_length")}
    for k in positive.get(part.shape, ()):
        if not getattr(part, k) > 0:
            raise ConfigError(f"must be > 0, got {getattr(part, k)}", where=f"{where}.{k}")
    if part.shape in ("box", "mesh") and not all(x > 0 for x in part.size):
        raise ConfigError(f"sizes must be > 0 m, got {part.size}", where=f"{where}.size")
    if part.shape == "mesh":
        if not Path(part.file).is_file():
            raise ConfigError(f"no such mesh file {part.file!r}", where=f"{where}.file")
        if not part.file.lower().endswith(".stl"):
            raise ConfigError(f"meshes are STL files, got {part.file!r}", where=f"{where}.file")
        n = _stl_triangles(Path(part.file))
        if n > MAX_MESH_TRIANGLES:
            raise ConfigError(f"{part.file!r} has {n} triangles, more than the limit of {MAX_MESH_TRIANGLES} "
                              "(ergosim.scenes.cellfile.MAX_MESH_TRIANGLES; simplify the mesh)",
                              where=f"{where}.file")
    if part.total_mass() is None and part.density is None:
        raise ConfigError("give mass [kg] or density [kg/m^3]", where=where)
    if (part.total_mass() or 1.0) <= 0 or (part.density is not None and part.density <= 0):
        raise ConfigError("mass and density must be > 0", where=where)
    if part.density is not None and part.density > MAX_DENSITY:
        raise ConfigError(f"density {part.density:g} kg/m^3 is above osmium's {MAX_DENSITY:g}, the densest "
                          "element (ergosim.scenes.cellfile.MAX_DENSITY)", where=f"{where}.density")
    if (part.total_mass() or 0.0) > MAX_PART_MASS:
        raise ConfigError(f"a mass of {part.total_mass():g} kg is above the limit of {MAX_PART_MASS:g} kg "
                          "(assumed: 4 x the NIOSH lifting equation's 23 kg; "
                          "ergosim.scenes.cellfile.MAX_PART_MASS)",
                          where=f"{where}.mass")
    if (part.xy is None) == (part.pos is None):
        raise ConfigError("give either xy (resting on a surface) or pos (a full pose)", where=where)
    return part


_SLOT_GAP = 0.005
"""Least distance between two slots' seats on one part [m] (assumed: the 5 mm the overlap checks allow)."""


def _stl_triangles(path: Path) -> int:
    """Triangles of the STL file at ``path``: a binary STL's count (bytes 80-84), or an ASCII STL's facets."""
    with path.open("rb") as f:
        head = f.read(84)
    size = path.stat().st_size
    if len(head) == 84 and size == 84 + 50 * int.from_bytes(head[80:84], "little"):
        return int.from_bytes(head[80:84], "little")
    return path.read_bytes().count(b"endfacet")


def _target(name: str, t: Any, where: str) -> Target:
    f = check_table(TargetTable, t, where)
    if "pos" in f:
        if "xy" in f or "on" in f:
            raise ConfigError("a target has either pos or on/xy, not both", where=where)
        return Target(name=name, kind="free", **f)
    for k in ("on", "xy", "part"):
        if k not in f:
            raise ConfigError(f"missing key {k!r} (or give pos for a free target)", where=where)
    return Target(name=name, kind="place", **f)


# -- checks ----------------------------------------------------------------------------------------------
def _check(spec: CellSpec, at) -> None:
    def need(ok: bool, entry: str, msg: str) -> None:
        if not ok:
            raise ConfigError(msg, where=at(entry))

    need(0.0005 <= spec.timestep <= 0.01, "timestep", f"must be in [0.0005, 0.01] s, got {spec.timestep}")
    need(spec.seat_tolerance > 0 and spec.seat_tolerance_deg > 0, "seat_tolerance", "tolerances must be > 0")
    need(spec.place_tolerance > 0 and spec.grasp_tolerance > 0, "place_tolerance", "tolerances must be > 0")
    need(1.4 <= spec.worker.stature <= 2.1, "worker.stature",
         f"stature must be in [1.4, 2.1] m, got {spec.worker.stature}")
    need(spec.worker.hand in ("right", "left"), "worker.hand",
         f"must be right or left, got {spec.worker.hand!r}")
    for segment, factor in spec.worker.human_scale:
        need(segment in SEGMENT_SCALES, "worker.human_scale",
             f"unknown segment scale {segment!r}; expected one of {', '.join(SEGMENT_SCALES)}")
        need(0.7 <= factor <= 1.3, "worker.human_scale",
             f"segment scale {segment}={factor} is outside 0.7..1.3")
    names = [f.name for f in spec.furniture] + [p.name for p in spec.parts] + [r.name for r in spec.robots]
    dup = {n for n in names if names.count(n) > 1}
    need(not dup, "furniture", f"names must be unique across furniture, parts and robots: {sorted(dup)}")
    surfaces = spec.surfaces()
    for f in spec.furniture:
        entry = f"furniture.{f.name}"
        for s in f.surfaces():
            need(all(x > 0 for x in s.size), entry, f"size must be > 0, got {s.size}")
            need(0.3 <= s.height <= 2.2, entry, f"{s.name} height must be in [0.3, 2.2] m, got {s.height}")
        if isinstance(f, Shelf):
            need(f.height - f.low_height >= 0.3, f"{entry}.height",
                 f"the top ledge must be >= 0.3 m above the lower one, got {f.height} and {f.low_height}")
            need(0.1 <= f.top_depth <= f.size[1] - 0.1, f"{entry}.top_depth",
                 f"top_depth must leave >= 0.1 m of the lower ledge open, got {f.top_depth}")
        if isinstance(f, Box):
            need(all(x > 0 for x in f.half), entry, f"half sizes must be > 0, got {f.half}")
            need(f.stand_to is None or f.stand_to in surfaces, f"{entry}.stand_to",
                 f"unknown surface {f.stand_to!r}; surfaces: {', '.join(surfaces)}")
    _check_overlaps(spec, at)
    for r in spec.robots:
        entry = f"robots.{r.name}"
        need(r.model in robot_names(), f"{entry}.model",
             f"unknown robot model {r.model!r}; valid robot models: {', '.join(robot_names())}")
        need(0.0 <= r.park_clearance <= 2.0, f"{entry}.park_clearance",
             f"must be in [0, 2] m, got {r.park_clearance}")
        need(r.support is None or r.support in surfaces, f"{entry}.support",
             f"unknown surface {r.support!r}; surfaces: {', '.join(surfaces)}")
        if r.support is not None:
            top = surfaces[r.support]
            need(r.base[2] >= top.height - 1e-6, f"{entry}.base",
                 f"the robot base at z={r.base[2]} m is below the top of its support {r.support} "
                 f"({top.height} m): it would stand inside it; raise the base or lower the {r.support}")
            need(top.contains(r.base[:2]), f"{entry}.base",
                 f"the robot base at xy={r.base[:2]} is not over its support {r.support} (centre "
                 f"{top.center}, size {top.size})")
        else:
            need(abs(r.base[2]) <= 0.005, f"{entry}.base",
                 f"the robot base at z={r.base[2]} m has nothing under it: give support = \"SURFACE\" (a "
                 "pedestal fills the gap) or stand it on the floor (z = 0)")
        for f in spec.furniture:
            for c, h in f.boxes():
                if np.all(np.abs(np.asarray(r.base) - c) < h - 1e-6):
                    raise ConfigError(f"the robot base {r.base} is inside furniture {f.name!r}",
                                      where=at(f"{entry}.base"))
    for p in spec.parts:
        _check_part_pose(spec, p, surfaces, at(f"parts.{p.name}"))
    _check_footprints(spec, at)
    for t in spec.targets:
        entry = f"targets.{t.name}"
        if t.kind == "place":
            need(t.on in surfaces, f"{entry}.on",
                 f"unknown surface {t.on!r}; surfaces: {', '.join(surfaces)}")
            need(surfaces[t.on].contains(t.xy, margin=0.02), f"{entry}.xy",
                 f"{t.xy} is not on the {t.on} (centre {surfaces[t.on].center}, size {surfaces[t.on].size})")
            need(t.part in {p.name for p in spec.parts}, f"{entry}.part",
                 f"unknown part {t.part!r}; parts: {', '.join(p.name for p in spec.parts)}")
    _check_actions(spec, at)


def _check_overlaps(spec: CellSpec, at) -> None:
    """Solid furniture boxes may touch but not interpenetrate by more than 5 mm (legs ignored)."""
    boxes = [(f.name, c, h) for f in spec.furniture for c, h in f.boxes()]
    for i, (n1, c1, h1) in enumerate(boxes):
        for n2, c2, h2 in boxes[i + 1:]:
            if n1 == n2:
                continue
            depth = h1 + h2 - np.abs(c1 - c2)
            if np.all(depth > 0.005):
                raise ConfigError(f"furniture {n1!r} and {n2!r} overlap "
                                  f"(by {float(depth.min()) * 1000:.0f} mm)", where=at(f"furniture.{n2}"))


def _check_part_pose(spec: CellSpec, p: Part, surfaces, where: str) -> None:
    if p.xy is not None:
        if p.on is None or p.on == "auto":
            s = spec.surface_under(p.xy)
            if s is None:
                raise ConfigError(f"no surface under xy={p.xy}: the part would float; surfaces: "
                                  f"{', '.join(surfaces)}", where=f"{where}.xy")
        else:
            if p.on not in surfaces:
                raise ConfigError(f"unknown surface {p.on!r}; surfaces: {', '.join(surfaces)}",
                                  where=f"{where}.on")
            s = surfaces[p.on]
        if not s.contains(p.xy, margin=0.02):
            raise ConfigError(f"{p.xy} is not on the {s.name} (centre {s.center}, size {s.size})",
                              where=f"{where}.xy")
        return
    # A full pose: the part's lowest point must touch a surface (within 5 mm) and not sink into furniture.
    bottom = p.pos[2] - _lowest(p)
    s = spec.surface_under(p.pos[:2])
    if s is None or bottom > s.height + 0.005:
        raise ConfigError(f"the part floats: its bottom is at z={bottom:.3f} m with "
                          f"{'no surface under it' if s is None else f'the {s.name} at {s.height} m'}",
                          where=f"{where}.pos")
    if bottom < s.height - 0.005:
        raise ConfigError(f"the part intersects the {s.name}: its bottom is at z={bottom:.3f} m, "
                          f"{(s.height - bottom) * 1000:.0f} mm below the top", where=f"{where}.pos")


def _check_footprints(spec: CellSpec, at) -> None:
    """Two parts resting on one surface are not at the same place: neither's centre is within the other's
    footprint. (Footprints that only overlap at their edges are left to the physics, which parts them.)"""
    resting = [(p, (spec.surface_under(p.xy) if p.on in (None, "auto") else spec.surfaces()[p.on]).name)
               for p in spec.parts if p.xy is not None]
    for i, (p, s) in enumerate(resting):
        for q, r in resting[i + 1:]:
            if s == r and (_covers(p, q.xy) or _covers(q, p.xy)):
                raise ConfigError(f"parts {p.name!r} and {q.name!r} are at the same place on the {s} (xy "
                                  f"{p.xy} and {q.xy}: one stands on the other's centre); move one of them",
                                  where=at(f"parts.{q.name}.xy"))


def _covers(part: Part, xy) -> bool:
    """Whether the point ``xy`` [m] is within the footprint of the resting ``part`` (its rectangle at its xy,
    turned by its yaw)."""
    yaw = math.radians(part.yaw)
    dx, dy = xy[0] - part.xy[0], xy[1] - part.xy[1]
    along, across = dx * math.cos(yaw) + dy * math.sin(yaw), -dx * math.sin(yaw) + dy * math.cos(yaw)
    hx, hy = part.half_extents[:2]
    return abs(along) <= hx and abs(across) <= hy


def _lowest(p: Part) -> float:
    """Depth [m] of the part's lowest point below its frame origin at its pose."""
    row = to_mat(from_rpy(p.rpy or (0.0, 0.0, p.yaw), degrees=True))[2]
    return float(np.abs(row) @ np.array(p.half_extents)) if p.shape != "socket_block" else p.rest_height()


def _check_actions(spec: CellSpec, at) -> None:
    parts = {p.name for p in spec.parts}
    targets = {t.name: t for t in spec.targets}
    slots = spec.slots()
    for a in spec.actions:
        entry = f"actions.{a.label}"
        if a.kind not in ACTION_KINDS:
            raise ConfigError(f"unknown action kind {a.kind!r}; kinds: {', '.join(ACTION_KINDS)}",
                              where=at(f"{entry}.kind"))
        if a.part not in parts:
            raise ConfigError(f"unknown part {a.part!r}; parts: {', '.join(sorted(parts))}",
                              where=at(f"{entry}.part"))
        kind = ACTION_KINDS[a.kind]
        if kind.target == "slot":
            if a.target not in slots:
                raise ConfigError(f"unknown slot {a.target!r}; slots: {', '.join(slots) or 'none'}",
                                  where=at(f"{entry}.target"))
            if slots[a.target].host == a.part:
                raise ConfigError(f"{a.part} cannot go into its own slot", where=at(f"{entry}.target"))
        else:
            want = "free" if kind.target == "free" else "place"
            of_kind = [n for n, t in targets.items() if t.kind == want]
            if a.target not in targets:
                raise ConfigError(f"unknown target {a.target!r}; targets: {', '.join(targets) or 'none'}",
                                  where=at(f"{entry}.target"))
            if targets[a.target].kind != want:
                what = ("a free target (pos = [x, y, z])" if want == "free"
                        else "a place target on a surface (on, xy, part)")
                raise ConfigError(f"a {a.kind} action goes to {what}; {a.target!r} is not one (those are: "
                                  f"{', '.join(of_kind) or 'none'})", where=at(f"{entry}.target"))
        presents = a.handover is not None and a.handover == a.target  # the robot presents it at its target
        if a.handover is not None and not presents and (a.handover not in targets
                                                        or targets[a.handover].kind != "free"):
            raise ConfigError(f"unknown handover pose {a.handover!r}; free targets: "
                              f"{', '.join(n for n, t in targets.items() if t.kind == 'free') or 'none'}, or "
                              f"the action's own target {a.target!r}", where=at(f"{entry}.handover"))
        if kind.holds and not 0 < a.turn_time <= TURN_TIME_MAX:
            raise ConfigError(f"a {a.kind} action needs turn_time in (0, {TURN_TIME_MAX:g}] s, got "
                              f"{a.turn_time:g}", where=at(f"{entry}.turn_time"))
        if not kind.holds and a.turn_time:
            raise ConfigError(f"turn_time belongs to actions that hold a seated part ("
                              f"{', '.join(k for k, v in ACTION_KINDS.items() if v.holds)}), not to "
                              f"{a.kind}", where=at(f"{entry}.turn_time"))
    same: dict[tuple[str, str, str], str] = {}
    for a in spec.actions:
        first = same.setdefault((a.kind, a.part, a.target), a.label)
        if first != a.label:
            raise ConfigError(f"actions {first!r} and {a.label!r} are one physical action ({a.kind} {a.part} "
                              f"to {a.target}) under two labels", where=at(f"actions.{a.label}"))
    into = [a.target for a in spec.actions if ACTION_KINDS[a.kind].seats]
    full = {s for s in into if into.count(s) > 1}
    if full:
        raise ConfigError(f"a slot takes one part, but two actions seat a part in {sorted(full)}",
                          where=at("actions"))
    seats = [a.part for a in spec.actions if ACTION_KINDS[a.kind].seats]
    dup = {p for p in seats if seats.count(p) > 1}
    if dup:
        raise ConfigError(f"a part is inserted by one action only, got {sorted(dup)} twice",
                          where=at("actions"))
