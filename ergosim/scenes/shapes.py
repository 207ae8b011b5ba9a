"""Part bodies from their shape: box, cylinder, mesh (STL or OBJ), socket block; each with its grasp sites.

A part is a free body whose frame is its centre. Visual geoms are group 2; the collision geoms (group 3)
carry the parts' own collision bits (:data:`PART_COLLISION`). Grasp sites give the TCP pose of a top-down
grasp with the fingers closing along the part's local y:

- ``<part>_grasp``: at the middle of the part lying as placed (TCP z = -local z), or just below its top
  (``grasp = "top"``: a screw by its head);
- ``<part>_grasp_end``: near the far end of the part's insertion axis once it stands inserted (a profile
  along local x: TCP z = -local x; a part inserted along local z: TCP z = -local z), for grasping a whole
  assembly by a part that sticks up out of it.

A socket block is a cast corner connector: a core cube with square sleeves (4 walls each) along the local
axes in ``sleeves``, each taking a profile of width ``bore`` with ``clearance``; its collision shape is the
outer envelope of core and sleeves as one box per sleeve (profiles never collide with it: insertion is a
weld within tolerance, not a contact simulation of a 0.5 mm fit).
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from ergosim.scenes.cellspec import Part
from ergosim.scenes.meshes import is_binary_stl, read_mesh

__all__ = ["PART_COLLISION", "add_part_body"]

PART_COLLISION = dict(contype=4, conaffinity=3)
"""Collision bits of the parts: their own bit 4, accepting bits 1 (furniture, floor) and 2 (the robot).
Parts therefore never collide with each other: a part carried past one already seated must not knock the
assembly, and insertion itself is a weld (Workcell.seat), not a contact fit."""

_AXIS = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}
_DOWN_Z = [0, 0, 1, 0]  # TCP frame of a top-down grasp: rotation of pi about y (z -> -z, x -> -x)
_DOWN_X = [np.cos(np.pi / 4), 0, -np.sin(np.pi / 4), 0]  # TCP x = local z, z = -local x: -90 deg about y
_END_GRASP = 0.025  # m below the +x end, where a standing profile is taken by its end (assumed: a finger pad)
_TOP_GRASP = 0.008  # m below the top, where a part is taken by its top: the bundled robots' finger pads reach
# 9.5-10 mm past the TCP (their finger meshes and boxes), so the pads stay clear of what the part stands in


def add_part_body(spec: mujoco.MjSpec, part: Part, pos, quat) -> mujoco.MjsBody:
    """Add free body ``part.name`` at world ``pos`` (3,) [m], ``quat`` wxyz, with geoms and grasp sites."""
    body = spec.worldbody.add_body(name=part.name, pos=list(pos), quat=list(quat))
    body.add_freejoint(name=part.name)
    rgba = list(part.rgba)
    if part.shape == "socket_block":
        _socket_block(body, part, rgba)
        return body
    mass = part.total_mass()
    inertial = dict(mass=mass) if mass is not None else dict(density=part.density)
    if part.shape == "box":
        body.add_geom(name=f"{part.name}_geom", type=mujoco.mjtGeom.mjGEOM_BOX, size=list(part.half_extents),
                      rgba=rgba, **inertial, **PART_COLLISION)
    elif part.shape == "cylinder":
        body.add_geom(name=f"{part.name}_geom", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[part.radius, part.length / 2], rgba=rgba, **inertial, **PART_COLLISION)
    else:
        _add_mesh(spec, part)
        body.add_geom(name=f"{part.name}_geom", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"{part.name}_mesh",
                      rgba=rgba, **inertial, **PART_COLLISION)
    hx, _, hz = part.half_extents
    top = [0.0, 0.0, hz - min(_TOP_GRASP, hz)]
    grasp = top if part.grasp == "top" else [0.0, 0.0, 0.0]
    body.add_site(name=f"{part.name}_grasp", pos=grasp, quat=_DOWN_Z, group=4)
    if part.insert_axis == "x" and hx > _END_GRASP:
        body.add_site(name=f"{part.name}_grasp_end", pos=[hx - _END_GRASP, 0, 0], quat=_DOWN_X, group=4)
    elif part.insert_axis == "z":
        body.add_site(name=f"{part.name}_grasp_end", pos=top, quat=_DOWN_Z, group=4)
    return body


def _add_mesh(spec: mujoco.MjSpec, part: Part) -> None:
    """The mesh asset ``<part>_mesh``: a binary STL by its file, any other by the vertices and triangles
    trimesh reads from it (:mod:`ergosim.scenes.meshes`)."""
    path = Path(part.file)
    if is_binary_stl(path):
        spec.add_mesh(name=f"{part.name}_mesh", file=str(part.file), scale=[part.scale] * 3)
        return
    vertices, faces = read_mesh(path, where=f"parts.{part.name}.file")
    spec.add_mesh(name=f"{part.name}_mesh", uservert=vertices.ravel().tolist(),
                  userface=faces.ravel().tolist(), scale=[part.scale] * 3)


def _socket_block(body: mujoco.MjsBody, part: Part, rgba: list[float]) -> None:
    c = part.core_half
    box = mujoco.mjtGeom.mjGEOM_BOX
    visual = dict(contype=0, conaffinity=0, group=2, density=part.density, rgba=rgba)
    body.add_geom(name=f"{part.name}_core", type=box, size=[c, c, c], **visual)
    inner = part.bore / 2 + part.clearance
    mid = inner + part.wall / 2
    half_len = part.sleeve_length / 2
    for axis in part.sleeves:
        a = _AXIS[axis]
        others = [i for i in range(3) if a[i] == 0]
        for k, (i, s) in enumerate([(others[0], 1), (others[0], -1), (others[1], 1), (others[1], -1)]):
            centre = a * (c + half_len)
            centre[i] = s * mid
            size = np.empty(3)
            size[int(np.argmax(a))] = half_len
            size[i] = part.wall / 2
            size[[j for j in others if j != i][0]] = c
            body.add_geom(name=f"{part.name}_sleeve_{axis}{k}", type=box, size=size.tolist(),
                          pos=centre.tolist(), **visual)
    # Collision: the outer envelope of core + sleeves as one massless box per sleeve (the first one with the
    # core); 3 boxes instead of 13 keep contacts few and the sim fast.
    solid = dict(group=3, density=0, rgba=rgba, **PART_COLLISION)
    envelopes = {"x": ([c + half_len, c, c], [half_len, 0, 0]), "y": ([c, half_len, c], [0, c + half_len, 0]),
                 "z": ([c, c, half_len], [0, 0, c + half_len])}
    for axis in part.sleeves:
        size, pos = envelopes[axis]
        body.add_geom(name=f"{part.name}_collision_{axis}", type=box, size=size, pos=pos, **solid)
    if "z" in part.sleeves:
        body.add_site(name=f"{part.name}_grasp", pos=[0, 0, c + half_len], quat=[0, 1, 0, 0], group=4)
    else:
        body.add_site(name=f"{part.name}_grasp", pos=[0, 0, c], quat=[0, 1, 0, 0], group=4)
