"""The corner-joint assembly of paper §7: the corner joint J with three hollows and the profiles L, S1, S2.

J is a cast aluminium corner connector: a core cube with three square sleeves (the hollows) along its
local +x, +y and +z axes. Its frame is the core centre; resting on a surface with the +z sleeve up, the core
centre is ``core_half`` above the surface. A profile is a square aluminium extrusion whose frame is its
centre, long axis local +x. A profile seated in a hollow touches the core face, long axis out of the hollow.

Masses use aluminium's density (2700 kg/m^3): J's walls are solid, a profile's box carries the net
cross-section of a real extrusion (``profile_area``), not a solid bar.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

__all__ = ["ALUMINIUM_DENSITY", "PROFILES", "PARTS", "HOLLOW_AXES", "PartDims", "hollow_pose",
           "rest_height", "add_corner_joint", "add_profile"]

ALUMINIUM_DENSITY = 2700.0
"""[kg/m^3]"""

PROFILES = ("L", "S1", "S2")

PART_COLLISION = dict(contype=4, conaffinity=3)
"""Collision bits of the parts: their own bit 4, accepting bits 1 (furniture, floor) and 2 (the robot).
Parts therefore never collide with each other: a profile carried past one already seated must not knock
the assembly, and insertion itself is a weld (Workcell.seat), not a contact fit."""

PARTS = ("J", *PROFILES)
HOLLOW_AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}
"""The three hollows of J, by the axis of J's frame they open along."""


@dataclass(frozen=True)
class PartDims:
    """Sizes [m] and net profile cross-section [m^2] (30x30 mm extrusion: about 3.3 cm^2, 0.9 kg/m)."""

    profile_width: float = 0.030
    profile_area: float = 3.3e-4
    s_length: float = 0.30
    l_length: float = 0.20
    clearance: float = 0.0005
    wall: float = 0.003
    sleeve_length: float = 0.030

    @property
    def core_half(self) -> float:
        """Half edge of J's core cube = outer half width of a sleeve."""
        return self.profile_width / 2 + self.clearance + self.wall

    def length(self, profile: str) -> float:
        return self.l_length if profile == "L" else self.s_length

    def profile_mass(self, profile: str) -> float:
        return ALUMINIUM_DENSITY * self.profile_area * self.length(profile)


def _quat_x_to(axis: str) -> np.ndarray:
    """Rotation taking local +x onto J's ``axis``; keeps a profile's faces parallel to J's faces."""
    if axis == "x":
        return np.array([1.0, 0, 0, 0])
    if axis == "y":  # yaw +90 deg
        return np.array([np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])
    return np.array([np.cos(np.pi / 4), 0, -np.sin(np.pi / 4), 0])  # pitch -90 deg: x -> z


def hollow_pose(dims: PartDims, profile: str, axis: str) -> tuple[np.ndarray, np.ndarray]:
    """Seated pose of ``profile`` in the hollow along ``axis`` in J's frame: pos (3,) [m], quat wxyz."""
    centre = (dims.core_half + dims.length(profile) / 2) * HOLLOW_AXES[axis]
    return centre, _quat_x_to(axis)


def rest_height(dims: PartDims, part: str) -> float:
    """Height [m] of the part's frame above the surface it rests on (J: +z sleeve up; profile lying)."""
    return dims.core_half if part == "J" else dims.profile_width / 2


def add_corner_joint(parent: mujoco.MjsBody, dims: PartDims, pos, quat,
                     rgba=(0.75, 0.76, 0.8, 1)) -> mujoco.MjsBody:
    """Add the free body ``J`` (visual: core + 3 sleeves of 4 walls) and its grasp site ``J_grasp``.

    ``J_grasp`` is the TCP pose for a top-down grasp across the +z sleeve: TCP z = -J z, fingers along J y.
    """
    body = parent.add_body(name="J", pos=list(pos), quat=list(quat))
    body.add_freejoint(name="J")
    c = dims.core_half
    box = mujoco.mjtGeom.mjGEOM_BOX
    visual = dict(contype=0, conaffinity=0, group=2, density=ALUMINIUM_DENSITY, rgba=list(rgba))
    body.add_geom(name="J_core", type=box, size=[c, c, c], **visual)
    inner = dims.profile_width / 2 + dims.clearance
    mid = inner + dims.wall / 2
    half_len = dims.sleeve_length / 2
    for axis, a in HOLLOW_AXES.items():
        others = [i for i in range(3) if a[i] == 0]
        for k, (i, s) in enumerate([(others[0], 1), (others[0], -1), (others[1], 1), (others[1], -1)]):
            centre = a * (c + half_len)
            centre[i] = s * mid
            size = np.empty(3)
            size[int(np.argmax(a))] = half_len
            size[i] = dims.wall / 2
            size[[j for j in others if j != i][0]] = c
            body.add_geom(name=f"J_sleeve_{axis}{k}", type=box, size=size.tolist(), pos=centre.tolist(),
                          **visual)
    # Collision shape: the outer envelope of core + sleeves as three massless boxes (core with the x
    # sleeve, the y sleeve, the z sleeve). The profiles never collide with J (insertion is a weld), so the
    # hollows need no contact geometry, and 3 boxes instead of 13 keep contacts few and the sim fast.
    solid = dict(group=3, density=0, rgba=list(rgba), **PART_COLLISION)
    body.add_geom(name="J_collision_x", type=box, size=[c + half_len, c, c], pos=[half_len, 0, 0], **solid)
    body.add_geom(name="J_collision_y", type=box, size=[c, half_len, c], pos=[0, c + half_len, 0], **solid)
    body.add_geom(name="J_collision_z", type=box, size=[c, c, half_len], pos=[0, 0, c + half_len], **solid)
    body.add_site(name="J_grasp", pos=[0, 0, c + half_len], quat=[0, 1, 0, 0], group=4)
    return body


def add_profile(parent: mujoco.MjsBody, dims: PartDims, name: str, pos, quat,
                rgba=(0.62, 0.66, 0.72, 1)) -> mujoco.MjsBody:
    """Add the free profile ``name`` (long axis local +x) with grasp sites.

    ``<name>_grasp``: TCP pose for a top-down grasp at the middle of the lying profile (TCP z = -local z,
    fingers across the width). ``<name>_grasp_end``: TCP pose for a top-down grasp 25 mm below the +x end
    when the profile stands on that end's opposite (TCP z = -local x).
    """
    length = dims.length(name)
    body = parent.add_body(name=name, pos=list(pos), quat=list(quat))
    body.add_freejoint(name=name)
    w = dims.profile_width / 2
    body.add_geom(name=f"{name}_geom", type=mujoco.mjtGeom.mjGEOM_BOX, size=[length / 2, w, w],
                  mass=dims.profile_mass(name), rgba=list(rgba), **PART_COLLISION)
    body.add_site(name=f"{name}_grasp", quat=[0, 0, 1, 0], group=4)  # rot pi about y: z -> -z, x -> -x
    # TCP x = local z, y = local y, z = -local x: rotation of -90 deg about local y
    body.add_site(name=f"{name}_grasp_end", pos=[length / 2 - 0.025, 0, 0],
                  quat=[np.cos(np.pi / 4), 0, -np.sin(np.pi / 4), 0], group=4)
    return body
