"""Build the Panda MJCF (``models/panda/panda.xml``) from example-robot-data's URDF.

Kinematics, joint limits, inertias and effort limits are read from the URDF; nothing is typed in by hand
except what a URDF cannot say (actuator gains, reflected rotor inertia, colours). Massless links joined by
fixed joints are folded into their parent (``panda_link8`` into ``panda_hand``'s pose) and a massless leaf
becomes a site (``panda_hand_tcp`` -> ``panda_tcp``), so MuJoCo's body frames equal the URDF link frames
and pinocchio on the same URDF gives the same forward kinematics.

Meshes are referenced by file name only; :func:`ergosim.robot.model.panda_spec` points ``meshdir`` at the
installed package when the model is loaded. The collision STLs serve as visuals too (MuJoCo reads no .dae).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim import quat
from ergosim.robot.urdf import Joint, Link, Origin, Urdf

__all__ = ["PandaGains", "ARM_JOINTS", "FINGER_JOINTS", "ARM_ACTUATORS", "GRIPPER_ACTUATOR", "TCP_SITE",
           "HOME_QPOS", "panda_xml"]

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
ARM_ACTUATORS = tuple(f"panda_actuator{i}" for i in range(1, 8))
GRIPPER_ACTUATOR = "panda_gripper"
TCP_SITE = "panda_tcp"
HOME_QPOS = (0.0, -0.785398, 0.0, -2.356194, 0.0, 1.570796, 0.785398)
"""The ``home`` arm configuration [rad]: Franka's ready pose (hand down, elbow up)."""

_SITES = {"panda_hand_tcp": TCP_SITE}
_DARK = {"panda_link7", "panda_hand", "panda_leftfinger", "panda_rightfinger"}


@dataclass(frozen=True)
class PandaGains:
    """Actuator parameters not in the URDF. ``kp`` [N m/rad] per arm joint, critically damped
    (``dampratio``); ``armature`` [kg m^2] reflected rotor inertia; ``gripper_kp`` [N/m] on the finger
    tendon, whose force limit ``gripper_force`` [N] is Franka Hand's 70 N continuous grip per finger x 2."""

    kp: tuple[float, ...] = (4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0)
    dampratio: float = 1.0
    armature: float = 0.1
    gripper_kp: float = 1000.0
    gripper_force: float = 140.0


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


def _geoms(link: Link, pad: str) -> list[str]:
    mat = "panda_dark" if link.name in _DARK else "panda_white"
    out = []
    for s in link.visuals:
        mesh = s.mesh
        out.append(f'{pad}<geom class="visual" mesh="{mesh}" material="{mat}"'
                   f'{_pose_attrs(np.array(s.origin.xyz), s.origin.quat)}/>')
    for s in link.collisions:
        attrs = _pose_attrs(np.array(s.origin.xyz), s.origin.quat)
        if s.kind == "mesh":
            out.append(f'{pad}<geom class="collision" mesh="{s.mesh}"{attrs}/>')
        else:
            half = np.array(s.size) / 2
            cls = "fingertip" if "finger" in link.name else "collision"
            out.append(f'{pad}<geom class="{cls}" type="box" size="{_vec(half)}"{attrs}/>')
    return out


def _inertial(link: Link, pad: str) -> list[str]:
    if link.inertial is None or link.inertial.mass <= 0:
        return []
    i = link.inertial
    return [f'{pad}<inertial pos="{_vec(i.origin.xyz)}" mass="{_num(i.mass)}" '
            f'fullinertia="{_vec(i.inertia)}"/>']


def _joint_xml(j: Joint, pad: str) -> str:
    kind = ' type="slide"' if j.kind == "prismatic" else ""
    cls = ' class="finger"' if j.kind == "prismatic" else ""
    return (f'{pad}<joint name="{j.name}"{cls}{kind} axis="{_vec(j.axis)}" '
            f'range="{_vec((j.lower, j.upper))}" actuatorfrcrange="{_vec((-j.effort, j.effort))}" '
            f'damping="{_num(j.damping)}"/>')


def _body(urdf: Urdf, link: Link, pos, quat, joint: Joint | None, pad: str) -> list[str]:
    cls = ' childclass="panda"' if joint is None and link.name == urdf.root() else ""
    lines = [f'{pad}<body name="{link.name}"{cls}{_pose_attrs(pos, quat)} gravcomp="1">']
    inner = pad + "  "
    lines += _inertial(link, inner)
    if joint is not None and joint.kind != "fixed":
        lines.append(_joint_xml(joint, inner))
    lines += _geoms(link, inner)
    lines += _children(urdf, link.name, np.zeros(3), np.array([1.0, 0, 0, 0]), inner)
    lines.append(f"{pad}</body>")
    return lines


def _children(urdf: Urdf, parent: str, pos, quat, pad: str) -> list[str]:
    out = []
    for j in urdf.children(parent):
        child = urdf.links[j.child]
        cpos, cquat = _compose(pos, quat, j.origin)
        if j.kind == "fixed" and _massless(child):
            grandchildren = urdf.children(child.name)
            if grandchildren:
                out += _children(urdf, child.name, cpos, cquat, pad)
            else:
                name = _SITES.get(child.name, child.name)
                out.append(f'{pad}<site name="{name}"{_pose_attrs(cpos, cquat)}/>')
            continue
        out += _body(urdf, child, cpos, cquat, j, pad)
    return out


def panda_xml(urdf: Urdf, gains: PandaGains = PandaGains(), timestep: float = 0.002) -> str:
    """MJCF text of the Panda with its hand, in menagerie layout (see module docstring)."""
    meshes = sorted({s.mesh for link in urdf.links.values() for s in (*link.visuals, *link.collisions)
                     if s.kind == "mesh"})
    root = urdf.links[urdf.root()]
    arm = [urdf.joint(n) for n in ARM_JOINTS]
    f1, f2 = (urdf.joint(n) for n in FINGER_JOINTS)
    lines = [
        '<mujoco model="panda">',
        '  <compiler angle="radian" autolimits="true"/>',
        "",
        f'  <option integrator="implicitfast" timestep="{_num(timestep)}"/>',
        "",
        "  <default>",
        '    <default class="panda">',
        f'      <joint armature="{_num(gains.armature)}"/>',
        '      <site size="0.005" group="4" rgba="0.9 0.2 0.2 1"/>',
        '      <default class="visual">',
        '        <geom type="mesh" contype="0" conaffinity="0" group="2" density="0"/>',
        "      </default>",
        # contype 2 / conaffinity 1: the arm touches the world and the parts but not itself (the real
        # Panda guards self-collision in its controller; planned paths never fold the arm onto itself).
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
        '    <material name="panda_white" rgba="0.95 0.95 0.95 1"/>',
        '    <material name="panda_dark" rgba="0.25 0.25 0.27 1"/>',
        *[f'    <mesh name="{m}" file="{m}.stl"/>' for m in meshes],
        "  </asset>",
        "",
        "  <worldbody>",
        *_body(urdf, root, np.zeros(3), np.array([1.0, 0, 0, 0]), None, "    "),
        "  </worldbody>",
        "",
        "  <tendon>",
        '    <fixed name="panda_split" class="panda">',
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
        *[f'    <position name="{a}" class="panda" joint="{j.name}" kp="{_num(kp)}" '
          f'dampratio="{_num(gains.dampratio)}" ctrlrange="{_vec((j.lower, j.upper))}" '
          f'forcerange="{_vec((-j.effort, j.effort))}"/>'
          for a, j, kp in zip(ARM_ACTUATORS, arm, gains.kp, strict=True)],
        f'    <position name="{GRIPPER_ACTUATOR}" class="panda" tendon="panda_split" '
        f'kp="{_num(gains.gripper_kp)}" dampratio="1" ctrlrange="{_vec((f1.lower, f1.upper))}" '
        f'forcerange="{_vec((-gains.gripper_force, gains.gripper_force))}"/>',
        "  </actuator>",
        "",
        "  <keyframe>",
        f'    <key name="home" qpos="{_vec((*HOME_QPOS, f1.upper, f2.upper))}" '
        f'ctrl="{_vec((*HOME_QPOS, f1.upper))}"/>',
        "  </keyframe>",
        "</mujoco>",
        "",
    ]
    return "\n".join(lines)
