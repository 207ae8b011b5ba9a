"""Build a robot's MJCF (``models/<name>/<name>.xml`` and its ``assets/``) from its URDF.

Kinematics, joint limits, inertias and effort limits are read from the URDF; nothing is typed in by hand
except what a URDF cannot say, which the robot's :class:`MjcfRecipe` holds (actuator gains, reflected rotor
inertia, the gripper's actuation, the home pose). Massless links joined by fixed joints are folded into
their parent and a massless leaf becomes a site (e.g. the TCP), so MuJoCo's body frames equal the URDF
link frames and pinocchio on the same URDF gives the same forward kinematics.

Assets: every collision mesh is copied (``<stem>.stl``); every COLLADA visual is converted
(:mod:`ergosim.robot.collada`) into one OBJ per colour (``<stem>_<k>.obj``) with a material of that
colour (decimated when the recipe says so, :mod:`ergosim.robot.decimate`), so the ``visual`` class shows the
real visual meshes and the ``collision`` class the coarse ones.
The MJCF names files relative to ``meshdir="assets"``, so the folder opens in plain MuJoCo.
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ergosim import quat
from ergosim.robot.assets import resolve_url
from ergosim.robot.collada import ColouredMesh, read_collada
from ergosim.robot.decimate import decimate
from ergosim.robot.urdf import Joint, Link, Origin, Shape, Urdf

__all__ = ["ArmActuation", "GripperActuation", "MjcfRecipe", "RobotFiles", "robot_mjcf", "obj_bytes"]


@dataclass(frozen=True)
class ArmActuation:
    """Position servos of the arm: ``kp`` [N m/rad] per joint, critically damped (``dampratio``);
    ``armature`` [kg m^2] reflected rotor inertia per arm joint."""

    kp: tuple[float, ...]
    dampratio: float = 1.0
    armature: float = 0.1


@dataclass(frozen=True)
class GripperActuation:
    """A parallel gripper: its two finger joints (the second mimics the first through an equality), a fixed
    tendon ``tendon`` = their mean opening, and the position actuator ``actuator`` on it (ctrl = opening per
    finger [m], the first finger's range) with gain ``kp`` [N/m] and force limit ``force`` [N]."""

    joints: tuple[str, str]
    tendon: str
    actuator: str
    kp: float
    force: float


@dataclass(frozen=True)
class MjcfRecipe:
    """What a URDF cannot say about a robot's MJCF.

    ``name``: model name, default class and material prefix; ``root``: the URDF link at the base (links
    above it, e.g. a ``world`` link, are left out); ``arm_joints`` / ``actuators``: the arm's joints and
    their position actuators, in order; ``sites``: massless URDF leaf links -> site names (the TCP);
    ``home``: the arm's ``home`` keyframe [rad], fingers open; ``finger_links``: links whose box collision
    geoms are finger pads (class ``fingertip``); ``skip_links``: massless links whose geoms are dropped
    (e.g. a 1 cm marker box); ``timestep`` [s]; ``visual_keep``: the fraction of each COLLADA visual part's
    triangles kept (:func:`~ergosim.robot.decimate.decimate`; 1 keeps them all), parts of up to
    ``visual_floor`` triangles kept whole. Collision meshes are always copied unchanged.
    """

    name: str
    root: str
    arm_joints: tuple[str, ...]
    actuators: tuple[str, ...]
    arm: ArmActuation
    gripper: GripperActuation
    sites: Mapping[str, str]
    home: tuple[float, ...]
    finger_links: tuple[str, ...] = ()
    skip_links: tuple[str, ...] = ()
    timestep: float = 0.002
    fallback_rgba: tuple[float, float, float, float] = (0.8, 0.8, 0.8, 1.0)
    visual_keep: float = 1.0
    visual_floor: int = 200


@dataclass(frozen=True, eq=False)
class RobotFiles:
    """``xml``: the MJCF text; ``assets``: file name -> bytes, the files of its ``assets/`` folder."""

    xml: str
    assets: dict[str, bytes] = field(default_factory=dict)


def obj_bytes(mesh: ColouredMesh) -> bytes:
    """A Wavefront OBJ of ``mesh``: its used vertices (10 µm resolution) and triangles, no normals (MuJoCo
    computes them, keeping creases)."""
    used = np.unique(mesh.faces)
    remap = np.full(len(mesh.vertices), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    out = io.StringIO()
    np.savetxt(out, mesh.vertices[used], fmt="v %.5f %.5f %.5f")
    np.savetxt(out, remap[mesh.faces] + 1, fmt="f %d %d %d")
    return out.getvalue().replace("-0.00000", "0.00000").encode()


def _num(x: float) -> str:
    s = f"{x:.12g}"
    return "0" if s in ("-0", "0") else s


def _vec(xs) -> str:
    return " ".join(_num(float(x)) for x in xs)


def _compose(pos: np.ndarray, q: np.ndarray, origin: Origin) -> tuple[np.ndarray, np.ndarray]:
    return pos + quat.rotate(q, np.array(origin.xyz)), quat.mul(q, origin.quat)


def _pose_attrs(pos: np.ndarray, quat: np.ndarray) -> str:
    out = f' pos="{_vec(pos)}"' if np.any(np.abs(pos) > 0) else ""
    if np.max(np.abs(quat - [1, 0, 0, 0])) > 1e-15:
        out += f' quat="{_vec(quat)}"'
    return out


def _massless(link: Link) -> bool:
    return (link.inertial is None or link.inertial.mass <= 0) and not link.visuals and not link.collisions


class _Builder:
    """One pass over the URDF tree, collecting the worldbody lines, the mesh assets and the materials."""

    def __init__(self, urdf: Urdf, recipe: MjcfRecipe) -> None:
        self.urdf, self.recipe = urdf, recipe
        self.assets: dict[str, bytes] = {}
        self.meshes: list[str] = []
        self.materials: dict[tuple[float, ...], str] = {}

    def material(self, rgba: tuple[float, ...]) -> str:
        key = tuple(round(c, 4) for c in rgba)
        if key not in self.materials:
            self.materials[key] = f"{self.recipe.name}_paint{len(self.materials)}"
        return self.materials[key]

    def mesh(self, name: str, filename: str, data: bytes) -> str:
        if filename not in self.assets:
            self.assets[filename] = data
            self.meshes.append(f'    <mesh name="{name}" file="{filename}"/>')
        return name

    def visual_geoms(self, s: Shape, pad: str) -> list[str]:
        attrs = _pose_attrs(np.array(s.origin.xyz), s.origin.quat)
        if s.kind != "mesh":
            half = np.array(s.size) / 2
            mat = self.material(self.recipe.fallback_rgba)
            return [f'{pad}<geom class="visual" type="box" size="{_vec(half)}" material="{mat}"{attrs}/>']
        path = resolve_url(s.file)
        if path.suffix.lower() != ".dae":
            mesh = self.mesh(f"{s.mesh}_0", f"{s.mesh}_0{path.suffix.lower()}", path.read_bytes())
            mat = self.material(self.recipe.fallback_rgba)
            return [f'{pad}<geom class="visual" mesh="{mesh}" material="{mat}"{attrs}/>']
        out = []
        r = self.recipe
        for k, read in enumerate(read_collada(path)):
            part = decimate(read, r.visual_keep, r.visual_floor) if r.visual_keep < 1.0 else read
            mesh = self.mesh(f"{s.mesh}_{k}", f"{s.mesh}_{k}.obj", obj_bytes(part))
            mat = self.material(part.rgba)
            out.append(f'{pad}<geom class="visual" mesh="{mesh}" material="{mat}"{attrs}/>')
        return out

    def collision_geoms(self, link: Link, s: Shape, pad: str) -> str:
        attrs = _pose_attrs(np.array(s.origin.xyz), s.origin.quat)
        if s.kind == "mesh":
            path = resolve_url(s.file)
            mesh = self.mesh(s.mesh, f"{s.mesh}{path.suffix.lower()}", path.read_bytes())
            return f'{pad}<geom class="collision" mesh="{mesh}"{attrs}/>'
        half = np.array(s.size) / 2
        cls = "fingertip" if link.name in self.recipe.finger_links else "collision"
        return f'{pad}<geom class="{cls}" type="box" size="{_vec(half)}"{attrs}/>'

    def geoms(self, link: Link, pad: str) -> list[str]:
        out = [g for s in link.visuals for g in self.visual_geoms(s, pad)]
        return out + [self.collision_geoms(link, s, pad) for s in link.collisions]

    def joint(self, j: Joint, pad: str) -> str:
        kind = ' type="slide"' if j.kind == "prismatic" else ""
        cls = ' class="finger"' if j.kind == "prismatic" else ""
        return (f'{pad}<joint name="{j.name}"{cls}{kind} axis="{_vec(j.axis)}" '
                f'range="{_vec((j.lower, j.upper))}" actuatorfrcrange="{_vec((-j.effort, j.effort))}" '
                f'damping="{_num(j.damping)}"/>')

    def body(self, link: Link, pos, quat, joint: Joint | None, pad: str) -> list[str]:
        cls = f' childclass="{self.recipe.name}"' if joint is None else ""
        lines = [f'{pad}<body name="{link.name}"{cls}{_pose_attrs(pos, quat)} gravcomp="1">']
        inner = pad + "  "
        if link.inertial is not None and link.inertial.mass > 0:
            i = link.inertial
            lines.append(f'{inner}<inertial pos="{_vec(i.origin.xyz)}" mass="{_num(i.mass)}" '
                         f'fullinertia="{_vec(i.inertia)}"/>')
        if joint is not None and joint.kind != "fixed":
            lines.append(self.joint(joint, inner))
        lines += self.geoms(link, inner)
        lines += self.children(link.name, np.zeros(3), np.array([1.0, 0, 0, 0]), inner)
        lines.append(f"{pad}</body>")
        return lines

    def children(self, parent: str, pos, quat, pad: str) -> list[str]:
        out = []
        for j in self.urdf.children(parent):
            child = self.urdf.links[j.child]
            cpos, cquat = _compose(pos, quat, j.origin)
            if j.kind == "fixed" and (_massless(child) or child.name in self.recipe.skip_links):
                if self.urdf.children(child.name):
                    out += self.children(child.name, cpos, cquat, pad)
                elif child.name in self.recipe.sites:
                    site = self.recipe.sites[child.name]
                    out.append(f'{pad}<site name="{site}"{_pose_attrs(cpos, cquat)}/>')
                continue
            out += self.body(child, cpos, cquat, j, pad)
        return out


def robot_mjcf(urdf: Urdf, recipe: MjcfRecipe) -> RobotFiles:
    """The MJCF text and asset files of ``urdf`` dressed by ``recipe``, in menagerie layout (module
    docstring): compiler, option, default, asset, worldbody, tendon, equality, actuator, keyframe."""
    r, g = recipe, recipe.gripper
    b = _Builder(urdf, recipe)
    body = b.body(urdf.links[r.root], np.zeros(3), np.array([1.0, 0, 0, 0]), None, "    ")
    arm = [urdf.joint(n) for n in r.arm_joints]
    f1, f2 = (urdf.joint(n) for n in g.joints)
    materials = [f'    <material name="{name}" rgba="{_vec(rgba)}"/>' for rgba, name in b.materials.items()]
    lines = [
        f'<mujoco model="{r.name}">',
        '  <compiler angle="radian" autolimits="true" meshdir="assets"/>',
        "",
        f'  <option integrator="implicitfast" timestep="{_num(r.timestep)}"/>',
        "",
        "  <default>",
        f'    <default class="{r.name}">',
        f'      <joint armature="{_num(r.arm.armature)}"/>',
        '      <site size="0.005" group="4" rgba="0.9 0.2 0.2 1"/>',
        '      <default class="visual">',
        '        <geom type="mesh" contype="0" conaffinity="0" group="2" density="0"/>',
        "      </default>",
        # contype 2 / conaffinity 1: the arm touches the world and the parts but not itself (the robot's
        # controller guards self-collision; planned paths never fold the arm onto itself).
        '      <default class="collision">',
        '        <geom type="mesh" group="3" contype="2" conaffinity="1" density="0"/>',
        '        <default class="fingertip">',
        '          <geom type="box" friction="1.2 0.02 0.001" solref="0.004 1" rgba="0.2 0.2 0.2 1"/>',
        "        </default>",
        "      </default>",
        '      <default class="finger">',
        '        <joint armature="0"/>',
        "      </default>",
        "    </default>",
        "  </default>",
        "",
        "  <asset>",
        *materials,
        *sorted(b.meshes),
        "  </asset>",
        "",
        "  <worldbody>",
        *body,
        "  </worldbody>",
        "",
        "  <tendon>",
        f'    <fixed name="{g.tendon}" class="{r.name}">',
        f'      <joint joint="{f1.name}" coef="0.5"/>',
        f'      <joint joint="{f2.name}" coef="0.5"/>',
        "    </fixed>",
        "  </tendon>",
        "",
        "  <equality>",
        # the URDF's <mimic>: the second finger copies the first
        f'    <joint joint1="{f1.name}" joint2="{f2.name}" solref="0.005 1"/>',
        "  </equality>",
        "",
        "  <actuator>",
        *[f'    <position name="{a}" class="{r.name}" joint="{j.name}" kp="{_num(kp)}" '
          f'dampratio="{_num(r.arm.dampratio)}" ctrlrange="{_vec((j.lower, j.upper))}" '
          f'forcerange="{_vec((-j.effort, j.effort))}"/>'
          for a, j, kp in zip(r.actuators, arm, r.arm.kp, strict=True)],
        f'    <position name="{g.actuator}" class="{r.name}" tendon="{g.tendon}" '
        f'kp="{_num(g.kp)}" dampratio="1" ctrlrange="{_vec((f1.lower, f1.upper))}" '
        f'forcerange="{_vec((-g.force, g.force))}"/>',
        "  </actuator>",
        "",
        "  <keyframe>",
        f'    <key name="home" qpos="{_vec((*r.home, f1.upper, f2.upper))}" '
        f'ctrl="{_vec((*r.home, f1.upper))}"/>',
        "  </keyframe>",
        "</mujoco>",
        "",
    ]
    return RobotFiles("\n".join(lines), b.assets)
