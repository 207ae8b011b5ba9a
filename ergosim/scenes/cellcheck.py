"""The checks of a workcell that need no physics: ranges, names that exist, and the geometry of what stands
where (furniture that overlaps, a robot base inside furniture or over nothing, parts that float, sink or
stand on each other's place, targets off their surface, actions that name no slot or target). Each is one
:class:`~ergosim.errors.ConfigError` naming the file and the entry (``at(entry)``).
"""

from __future__ import annotations

import math

import numpy as np

from ergosim.errors import ConfigError
from ergosim.human.anthropometry import SEGMENT_SCALES
from ergosim.quat import from_rpy, to_mat
from ergosim.robot.robot_model import robot_names
from ergosim.scenes.cellspec import ACTION_KINDS, Box, CellSpec, Part, Shelf

__all__ = ["check_cell", "TURN_TIME_MAX", "VIEW_DISTANCE_MAX"]

TURN_TIME_MAX = 600.0
"""Longest hold-and-turn of a fastening [s] (assumed: ten minutes is no longer one action; the worker's motion
holds a pose per mocap frame of it)."""


VIEW_DISTANCE_MAX = 100.0
"""Farthest camera of a view [m] (assumed: a workcell is a few metres across; farther, it is a dot)."""


def check_cell(spec: CellSpec, at) -> None:
    """Every check of the parsed cell ``spec``; ``at(entry)`` names the file and the entry."""
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
            need(0.1 <= f.top_depth <= f.depth - 0.1, f"{entry}.top_depth",
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
            for c, h, yaw in f.boxes():
                if np.all(np.abs(_in_box(np.asarray(r.base, dtype=float), c, yaw)) < h - 1e-6):
                    raise ConfigError(f"the robot base {r.base} is inside furniture {f.name!r}",
                                      where=at(f"{entry}.base"))
    for p in spec.parts:
        _check_part_pose(spec, p, surfaces, at(f"parts.{p.name}"))
    _check_footprints(spec, at)
    for v in spec.views:
        need(-90.0 <= v.elevation <= 90.0, f"views.{v.name}.elevation",
             f"elevation must be in [-90, 90] deg, got {v.elevation:g}")
        need(0.0 < v.distance <= VIEW_DISTANCE_MAX, f"views.{v.name}.distance",
             f"distance must be in (0, {VIEW_DISTANCE_MAX:g}] m, got {v.distance:g}")
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
    boxes = [(f.name, c, h, yaw) for f in spec.furniture for c, h, yaw in f.boxes()]
    for i, (n1, c1, h1, y1) in enumerate(boxes):
        for n2, c2, h2, y2 in boxes[i + 1:]:
            if n1 == n2:
                continue
            depth = _overlap(c1, h1, y1, c2, h2, y2)
            if np.all(depth > 0.005):
                raise ConfigError(f"furniture {n1!r} and {n2!r} overlap "
                                  f"(by {float(depth.min()) * 1000:.0f} mm)", where=at(f"furniture.{n2}"))


def _overlap(c1, h1, yaw1: float, c2, h2, yaw2: float) -> np.ndarray:
    """How far two boxes turned about z (centres, half sizes [m], yaws [deg]) overlap along each separating
    axis [m]: z and the four edge directions of their footprints (two boxes standing upright are apart
    exactly when one of these is <= 0). Unturned boxes: the overlap along x, y, z."""
    if yaw1 == 0.0 and yaw2 == 0.0:
        return h1 + h2 - np.abs(c1 - c2)
    d = c2[:2] - c1[:2]
    out = [h1[2] + h2[2] - abs(c1[2] - c2[2])]
    for yaw in (yaw1, yaw2):
        for a in (math.radians(yaw), math.radians(yaw + 90.0)):
            u = np.array([math.cos(a), math.sin(a)])
            reach = sum(_extent(h, y, u) for h, y in ((h1, yaw1), (h2, yaw2)))
            out.append(reach - abs(float(d @ u)))
    return np.array(out)


def _extent(half, yaw: float, u: np.ndarray) -> float:
    """Half the width [m] of a footprint (``half`` sizes along its axes, turned by ``yaw`` [deg]) along the
    unit direction ``u`` (2,)."""
    a = math.radians(yaw)
    return half[0] * abs(u[0] * math.cos(a) + u[1] * math.sin(a)) + half[1] * abs(-u[0] * math.sin(a)
                                                                                 + u[1] * math.cos(a))


def _in_box(point: np.ndarray, centre: np.ndarray, yaw: float) -> np.ndarray:
    """The world ``point`` (3,) [m] relative to a box's ``centre``, in the box's frame turned by ``yaw``
    [deg]."""
    d = point - centre
    if yaw == 0.0:
        return d
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1], d[2]])


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
