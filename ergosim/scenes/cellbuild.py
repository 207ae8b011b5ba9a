"""Compile a :class:`~ergosim.scenes.cellspec.CellSpec` into a MuJoCo workcell.

Build order (it fixes body, geom and constraint order, and so the physics): furniture in file order, the
robots, the human, the parts in file order, the slots' seat sites, the targets' sites, the welds (holders
× parts, then one seat per inserted part in action order, then one receiver weld per part handed over),
the ``home`` keyframe.
"""

from __future__ import annotations

import mujoco

from ergosim.quat import from_axis_to, from_rpy, from_yaw_deg
from ergosim.robot.handle import robot_prefix
from ergosim.robot.robot_model import get_robot
from ergosim.scenes import build
from ergosim.scenes.action_kinds import action_kind
from ergosim.scenes.cellspec import Box, CellSpec, Shelf, Table
from ergosim.scenes.clearance import check_clearance
from ergosim.scenes.shapes import add_part_body
from ergosim.scenes.surface import Surface, turned
from ergosim.scenes.workcell import ActionGeometry, Workcell

__all__ = ["build_cell", "cell_mjspec", "seat_site", "present_site", "action_geometry", "PRESENT_STANDOFF"]

PRESENT_STANDOFF = 0.06
"""How far short of its target a robot presents a part handed over at the target [m]: along the slot's axis
for an insertion, above it for a place; the robot's own insertion stroke (``SkillParams.insert_approach``),
which the worker then completes."""


def seat_site(slot_host: str, part: str) -> str:
    """Name of the site where ``part`` sits when seated in its slot of ``slot_host``."""
    return f"{slot_host}_hollow_{part}"


def present_site(action: str) -> str:
    """Name of the site where a robot presents the part of ``action`` (``handover`` = the action's target):
    the target's pose, :data:`PRESENT_STANDOFF` out along the way in."""
    return f"{action}_present"


def action_geometry(spec: CellSpec) -> dict[str, ActionGeometry]:
    slots = spec.slots()
    out = {}
    for a in spec.actions:
        if action_kind(a.kind).seats:
            target = seat_site(slots[a.target].host, a.part)
        else:
            target = a.target
        handover = present_site(a.label) if a.handover is not None and a.handover == a.target else a.handover
        out[a.label] = ActionGeometry(a.label, a.part, a.kind, target, handover=handover,
                                      turn_time=a.turn_time)
    return out


def _furniture(mspec: mujoco.MjSpec, spec: CellSpec) -> None:
    surfaces = spec.surfaces()
    for f in spec.furniture:
        if isinstance(f, Table):
            build.add_table(mspec, f.surfaces()[0], thickness=f.thickness, legs=f.legs, rgba=f.rgba)
        elif isinstance(f, Shelf):
            top, low = f.ledges()
            build.add_table(mspec, low, thickness=f.thickness, legs=True, rgba=f.rgba)
            build.add_table(mspec, top, thickness=f.thickness, legs=False, rgba=f.rgba)
            rise = (top.height - low.height) / 2
            for i, (x, y) in enumerate(_post_corners(top)):
                build.add_box(mspec, f"{f.name}_post{i}", (x, y, low.height + rise), (0.02, 0.02, rise),
                              yaw=f.yaw)
        elif isinstance(f, Box):
            build.add_box(mspec, f.name, f.center, f.half, rgba=f.rgba, yaw=f.yaw)
            if f.stand_to is not None:
                (mx, my, mz), hz = f.center, f.half[2]
                floor = surfaces[f.stand_to].height
                stand = (mz - hz - floor) / 2
                x, y = turned((mx, my), f.stand_offset, f.yaw)
                build.add_box(mspec, f"{f.name}_stand", (x, y, floor + stand), (*f.stand_half, stand),
                              yaw=f.yaw)


def _post_corners(top: Surface) -> list[tuple[float, float]]:
    """World (x, y) [m] of a shelf's four posts, 20 mm inside the corners of its top ledge."""
    (cx, cy), (sx, sy) = top.center, top.size
    if top.yaw == 0.0:  # the arithmetic of the unturned shelf, bit for bit
        front, back = cy + sy / 2 - 0.02, cy - sy / 2 + 0.02
        return [(cx - sx / 2 + 0.02, front), (cx + sx / 2 - 0.02, front),
                (cx - sx / 2 + 0.02, back), (cx + sx / 2 - 0.02, back)]
    ax, ay = sx / 2 - 0.02, sy / 2 - 0.02
    corners = [(-1, 1), (1, 1), (-1, -1), (1, -1)]
    return [turned(top.center, (dx * ax, dy * ay), top.yaw) for dx, dy in corners]


def _part_pose(spec: CellSpec, part) -> tuple[list[float], list[float]]:
    if part.xy is not None:
        surface = spec.surfaces()[part.on] if part.on not in (None, "auto") else spec.surface_under(part.xy)
        return [part.xy[0], part.xy[1], surface.height + part.rest_height()], from_yaw_deg(part.yaw)
    if part.rpy is not None:
        return list(part.pos), from_rpy(part.rpy, degrees=True)
    return list(part.pos), from_yaw_deg(part.yaw)


def _assemble(spec: CellSpec) -> tuple[mujoco.MjSpec, dict[str, str], mujoco.MjModel, tuple]:
    """The scene's MjSpec before its keyframe, the holders' hand bodies, the human's articulated model and
    the robots' (name, prefix) pairs."""
    m = build.new_spec(spec.name, spec.timestep)
    _furniture(m, spec)
    surfaces = spec.surfaces()
    hands: dict[str, str] = {}
    prefixes = tuple((r.name, robot_prefix(i, r.name), get_robot(r.model), r.park_clearance)
                     for i, r in enumerate(spec.robots))
    for r, (_, prefix, kind, _) in zip(spec.robots, prefixes, strict=True):
        support = surfaces[r.support].height if r.support is not None else None
        build.attach_robot(m, kind, r.base, r.yaw, spec.timestep, support_height=support, prefix=prefix)
        hands[r.name] = f"{prefix}{kind.hand}"
    human = build.attach_human(m, spec.worker)
    hands.update(build.human_hand_bodies(m))
    bodies = {}
    for part in spec.parts:
        pos, quat = _part_pose(spec, part)
        bodies[part.name] = build_part = add_part_body(m, part, pos, quat)
        del build_part
    slots = spec.slots()
    seats = []
    for a in spec.actions:
        if not action_kind(a.kind).seats:
            continue
        slot = slots[a.target]
        part = spec.part(a.part)
        centre = [slot.at[i] + part.insert_half_length * slot.axis[i] for i in range(3)]
        quat = from_axis_to(part.insert_axis, slot.axis).tolist()
        bodies[slot.host].add_site(name=seat_site(slot.host, a.part), pos=centre, quat=quat, group=4)
        if a.handover == a.target:
            out = [centre[i] + PRESENT_STANDOFF * slot.axis[i] for i in range(3)]
            bodies[slot.host].add_site(name=present_site(a.label), pos=out, quat=quat, group=4)
        seats.append((slot.host, a.part))
    for t in spec.targets:
        if t.kind == "place":
            pos = [*t.xy, surfaces[t.on].height + spec.part(t.part).rest_height()]
        else:
            pos = list(t.pos)
        m.worldbody.add_site(name=t.name, pos=pos, quat=from_yaw_deg(t.yaw), group=4)
        for a in spec.actions:
            if a.handover is not None and a.handover == a.target == t.name:
                above = [pos[0], pos[1], pos[2] + PRESENT_STANDOFF]
                m.worldbody.add_site(name=present_site(a.label), pos=above, quat=from_yaw_deg(t.yaw), group=4)
    # insertion is a weld within tolerance (Workcell.seat), not a contact simulation of the fit
    for host, part in seats:
        m.add_exclude(bodyname1=host, bodyname2=part)
    received = list(dict.fromkeys(a.part for a in spec.actions if action_kind(a.kind).received))
    build.add_welds(m, hands, [p.name for p in spec.parts], seats, received)
    return m, hands, human, prefixes


def cell_mjspec(spec: CellSpec) -> mujoco.MjSpec:
    """The MjSpec of ``spec``'s scene, keyframe included (compiled once on the way), e.g. to save as MJCF."""
    m, _, _, prefixes = _assemble(spec)
    build.finish(m, where=spec.source, robots=prefixes)
    return m


def build_cell(spec: CellSpec) -> Workcell:
    """The compiled :class:`Workcell` of ``spec`` (reset to its ``home`` keyframe)."""
    m, hands, human, prefixes = _assemble(spec)
    model, parks = build.finish(m, where=spec.source, robots=prefixes)
    cell = Workcell(spec, model, action_geometry(spec), hands, human=human, parks=parks)
    # nothing inside furniture at the ready pose, where every robot's inverse kinematics starts and near
    # which its transits pass, nor at the park pose (the home keyframe), where each run starts
    for handle in cell.robot_handles.values():
        cell.data.qpos[handle.arm_qpos] = handle.robot.home
    mujoco.mj_kinematics(cell.model, cell.data)
    check_clearance(spec, cell.model, cell.data, "ready pose")
    cell.reset()
    check_clearance(spec, cell.model, cell.data, "park pose")
    return cell
