"""Workcell files (TOML): read, override by dotted path, and parse into a checked :class:`CellSpec`.

The format is documented field by field in docs/workcell_format.md and declared as a schema in
:mod:`ergosim.scenes.cell_schema`. A file is parsed to a plain dict, overrides are applied to that dict
(``parts.L.xy = "0.2,0.8"``, or a legacy alias such as ``l_xy`` declared in the file's ``[aliases]`` table)
by the one override of every format, then :func:`parse_cell` checks each table against its schema, builds
the frozen :class:`CellSpec` and runs the checks of :mod:`ergosim.scenes.cellcheck` (names, ranges,
geometry). Every problem is one :class:`ConfigError` naming the file, the entry and what was expected.
"""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError
from ergosim.robot.robot_model import default_robot
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
from ergosim.scenes.cellcheck import TURN_TIME_MAX, check_cell
from ergosim.scenes.cellspec import (
    COUPLINGS,
    SHAPES,
    SHELF_BACKS,
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
from ergosim.scenes.meshes import (
    MAX_MESH_TRIANGLES,
    MESH_SUFFIXES,
    is_binary_stl,
    mesh_triangles,
    read_mesh,
)
from ergosim.schema.document import check_table, override, paths
from ergosim.schema.values import AXES

__all__ = ["read_cell_file", "parse_cell", "apply_cell_overrides", "override_paths", "cell_keys",
           "MAX_FILE_BYTES", "TURN_TIME_MAX", "MAX_PART_MASS", "MAX_DENSITY", "MAX_MESH_TRIANGLES"]

MAX_FILE_BYTES = 4 * 1024 * 1024
"""Largest workcell or scenario file read [bytes]; a cell is a few kB."""

MAX_PART_MASS = 100.0
"""Heaviest part [kg] (assumed: four times the load constant of the NIOSH lifting equation, 23 kg (Waters et
al. 1993), far beyond what is carried by hand in an assembly cell; 1e30 kg made the physics diverge)."""
MAX_DENSITY = 22_590.0
"""Densest part material [kg/m^3]: osmium, the densest element (CRC Handbook of Chemistry and Physics)."""


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
    fields = check_table(TopTable, top, source, required=("name",), top=True)
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
    check_cell(spec, at)
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
    if f.get("back", "-y") not in SHELF_BACKS:
        raise ConfigError(f"the side the top ledge stands against is one of {', '.join(SHELF_BACKS)} (in the "
                          f"shelf's own frame), got {f['back']!r}", where=f"{where}.back")
    if not -360.0 <= f.get("yaw", 0.0) <= 360.0:
        raise ConfigError(f"yaw must be in [-360, 360] deg, got {f['yaw']:g}", where=f"{where}.yaw")
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
        if not part.file.lower().endswith(MESH_SUFFIXES):
            raise ConfigError(f"meshes are STL (binary or ASCII) or OBJ files, got {part.file!r}",
                              where=f"{where}.file")
        n = mesh_triangles(Path(part.file))
        if n > MAX_MESH_TRIANGLES:
            raise ConfigError(f"{part.file!r} has {n} triangles, more than the limit of {MAX_MESH_TRIANGLES} "
                              "(ergosim.scenes.meshes.MAX_MESH_TRIANGLES; simplify the mesh)",
                              where=f"{where}.file")
        if not is_binary_stl(Path(part.file)):
            read_mesh(Path(part.file), where=f"{where}.file")  # a malformed file fails here, not in MuJoCo
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
