"""MJCF text of the kinematic human upper body, generated from :class:`~ergosim.human.anthropometry.Segments`.

The layout follows mujoco_menagerie (compiler, default, asset, worldbody, keyframe; 2-space indent). All
geoms are capsules with ``contype=0 conaffinity=0``: the human is driven kinematically and never pushes the
robot or a part (a held part is attached by a weld made by the scene, see ``Workcell.grasp``). Every body has
``gravcomp="1"`` and the hinges are damped so that a physics step between two mocap frames leaves the human
where the stream put it. Default classes are prefixed ``human_`` so that the human can be attached into a
scene that already has ``visual``/``collision`` classes (a robot's) without a name clash.
"""

from __future__ import annotations

import math
import re

from ergosim.human.anthropometry import Segments
from ergosim.human.joints import joint_spec
from ergosim.human.segment_mass import segment_inertials

__all__ = ["HOME_POSTURE", "humanoid_xml"]

HOME_POSTURE: dict[str, float] = {"elbow_flexion": 10.0, "left_elbow_flexion": 10.0}
"""The ``home`` keyframe [deg]: upright, arms hanging, elbows relaxed; every other angle 0."""


def _num(x: float) -> str:
    s = f"{x:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _vec(*xs: float) -> str:
    return " ".join(_num(x) for x in xs)


def _joint(pad: str, name: str, range_: tuple[float, float] | None = None) -> str:
    j = joint_spec(name)
    lo, hi = range_ or j.range_deg
    if j.kind == "slide":
        return f'{pad}<joint name="{name}" type="slide" axis="{_vec(*j.axis)}" range="{_vec(lo, hi)}"/>'
    lo, hi = math.radians(lo), math.radians(hi)
    return f'{pad}<joint name="{name}" axis="{_vec(*j.axis)}" range="{_vec(lo, hi)}"/>'


def _capsule(pad: str, name: str, a: tuple, b: tuple, r: float, cls: str = "human_visual",
             mat: str = "") -> str:
    material = f' material="{mat}"' if mat else ""
    return (f'{pad}<geom name="{name}" class="{cls}" fromto="{_vec(*a, *b)}" size="{_num(r)}"'
            f"{material}/>")


def _inertial(pad: str, inertials: dict, body: str) -> str:
    pos, mass, inertia = inertials[body]
    sig = " ".join(f"{x:.4g}" for x in inertia)
    return f'{pad}<inertial pos="{_vec(*pos)}" mass="{mass:.4g}" diaginertia="{sig}"/>'


def _arm(s: Segments, side: str, pad: str, inertials: dict) -> list[str]:
    """Clavicle -> upper arm -> forearm -> hand for ``side`` in ("right", "left")."""
    sgn = -1.0 if side == "right" else 1.0  # y of this side
    pre = "" if side == "right" else "left_"
    h = s.stature
    sc = (s.sc_forward, sgn * s.sc_lateral, s.lumbar_to_c7 - s.c7_to_shoulder - s.sc_below)
    gh = (-s.sc_forward, sgn * (s.shoulder_half_width - s.sc_lateral), s.sc_below)
    palm = (0.0, -sgn * 0.014 * h, -0.5 * s.hand)  # palm faces the midline
    p1, p2, p3, p4 = (pad + "  " * k for k in range(1, 5))
    return [
        f'{pad}<body name="human_{side}_clavicle" pos="{_vec(*sc)}" gravcomp="1">',
        _inertial(p1, inertials, "clavicle"),
        _joint(p1, pre + "shoulder_elevation"),
        _capsule(p1, f"human_{side}_clavicle", (0, 0, 0), gh, 0.018 * h, mat="human_cloth"),
        f'{p1}<body name="human_{side}_upper_arm" pos="{_vec(*gh)}" gravcomp="1">',
        _inertial(p2, inertials, "upper_arm"),
        _joint(p2, pre + "shoulder_flexion"),
        _joint(p2, pre + "shoulder_abduction"),
        _joint(p2, pre + "shoulder_rotation"),
        _capsule(p2, f"human_{side}_upper_arm", (0, 0, 0), (0, 0, -s.upper_arm), 0.026 * h,
                 mat="human_cloth"),
        f'{p2}<body name="human_{side}_forearm" pos="{_vec(0, 0, -s.upper_arm)}" gravcomp="1">',
        _inertial(p3, inertials, "forearm"),
        _joint(p3, pre + "elbow_flexion"),
        _joint(p3, pre + "forearm_pronation"),
        _capsule(p3, f"human_{side}_forearm", (0, 0, 0), (0, 0, -s.forearm), 0.020 * h),
        f'{p3}<body name="human_{side}_hand" pos="{_vec(0, 0, -s.forearm)}" gravcomp="1">',
        _inertial(p4, inertials, "hand"),
        _joint(p4, pre + "wrist_flexion"),
        _joint(p4, pre + "wrist_deviation"),
        _capsule(p4, f"human_{side}_hand", (0, 0, -0.12 * s.hand), (0, 0, -0.8 * s.hand), 0.012 * h),
        _capsule(p4, f"human_{side}_hand_collision", (0, 0, -0.12 * s.hand), (0, 0, -0.8 * s.hand),
                 0.012 * h, cls="human_collision"),
        f'{p4}<site name="human_hand_{side}" pos="{_vec(*palm)}"/>',
        f"{p3}</body>",
        f"{p2}</body>",
        f"{p1}</body>",
        f"{pad}</body>",
    ]


def _leg(s: Segments, side: str, pad: str, inertials: dict) -> list[str]:
    """Thigh -> shank -> foot for ``side``, hanging from the pelvis; their hinges follow the stance's knee
    and ankle (:mod:`ergosim.human.legs`). The foot spans heel to toe, a quarter of its length behind the
    ankle (:func:`foot_extent`)."""
    h = s.stature
    y = (-1.0 if side == "right" else 1.0) * 0.55 * s.hip_half_width
    pre = "" if side == "right" else "left_"
    p1, p2, p3 = (pad + "  " * k for k in range(1, 4))
    heel, toe = foot_extent(s)
    r = 0.02 * h
    return [
        f'{pad}<body name="human_{side}_thigh" pos="{_vec(0, y, 0)}" gravcomp="1">',
        _inertial(p1, inertials, "thigh"),
        _joint(p1, pre + "hip_flexion"),
        _capsule(p1, f"human_{side}_thigh", (0, 0, 0), (0, 0, -s.thigh), 0.034 * h, mat="human_trousers"),
        f'{p1}<body name="human_{side}_shank" pos="{_vec(0, 0, -s.thigh)}" gravcomp="1">',
        _inertial(p2, inertials, "shank"),
        _joint(p2, pre + "knee_flexion"),
        _capsule(p2, f"human_{side}_shank", (0, 0, 0), (0, 0, -s.shank), 0.024 * h, mat="human_trousers"),
        f'{p2}<body name="human_{side}_foot" pos="{_vec(0, 0, -s.shank)}" gravcomp="1">',
        _inertial(p3, inertials, "foot"),
        _joint(p3, pre + "ankle_dorsiflexion"),
        _capsule(p3, f"human_{side}_foot", (heel + r, 0, 0), (toe - r, 0, 0), r, mat="human_trousers"),
        f"{p2}</body>",
        f"{p1}</body>",
        f"{pad}</body>",
    ]


def _header(model_name: str) -> list[str]:
    """The document's opening: compiler, default classes and materials."""
    return [
        f'<mujoco model="{model_name}">',
        '  <compiler angle="radian" autolimits="true"/>',
        "",
        "  <default>",
        '    <default class="human">',
        '      <joint type="hinge" damping="2" armature="0.05"/>',
        '      <geom type="capsule" contype="0" conaffinity="0" density="1000"/>',
        '      <site type="sphere" size="0.01" group="4" rgba="1 0.3 0.1 1"/>',
        '      <default class="human_visual">',
        '        <geom group="2" material="human_skin"/>',
        "      </default>",
        '      <default class="human_collision">',
        '        <geom group="3" density="0"/>',
        "      </default>",
        "    </default>",
        "  </default>",
        "",
        "  <asset>",
        '    <material name="human_skin" rgba="0.87 0.72 0.6 1"/>',
        '    <material name="human_cloth" rgba="0.25 0.4 0.6 1"/>',
        '    <material name="human_trousers" rgba="0.2 0.2 0.25 1"/>',
        "  </asset>",
        "",
    ]


def foot_extent(s: Segments) -> tuple[float, float]:
    """(heel, toe) x of the foot from the ankle [m]: the ankle a quarter of the foot's length (Drillis &
    Contini, 0.152 H) from the heel (assumed: the lateral malleolus sits about a quarter of the foot's
    length in front of the heel)."""
    return -0.25 * s.foot, 0.75 * s.foot


def humanoid_xml(s: Segments, model_name: str = "humanoid_upper", keyframe: str | None = "home") -> str:
    """The MJCF document of the human with segments ``s``.

    The root body ``human_base`` has no joint and sits on the floor at the worker's position, facing +x:
    attach it to a frame there. The pelvis above it steps (``pelvis_x``, ``pelvis_y``), turns
    (``pelvis_rotation``) and moves over the feet with the knees and ankles (``knee_flexion``,
    ``ankle_dorsiflexion`` and the joints that follow them). Segment masses and centres of mass are de
    Leva's (:mod:`ergosim.human.segment_mass`).
    """
    h = s.stature
    hip_y = 0.55 * s.hip_half_width
    sh_z = s.lumbar_to_c7 - s.c7_to_shoulder
    inertials = segment_inertials(s)
    lines = [
        *_header(model_name),
        "  <worldbody>",
        '    <body name="human_base" childclass="human">',
        f'      <body name="human_pelvis" pos="{_vec(0, 0, s.hip_height)}" gravcomp="1">',
        _inertial("        ", inertials, "pelvis"),
        *(_joint("        ", n) for n in ("pelvis_x", "pelvis_y", "pelvis_rotation")),
        _joint("        ", "pelvis_shift"),
        _joint("        ", "pelvis_drop", (0.0, s.thigh + s.shank)),
        _capsule("        ", "human_pelvis", (0, -hip_y, 0.03 * h), (0, hip_y, 0.03 * h), 0.055 * h,
                 mat="human_trousers"),
        *_leg(s, "right", "        ", inertials),
        *_leg(s, "left", "        ", inertials),
    ]
    p1, p2, p3 = "        ", "          ", "            "
    lines += [
        f'{p1}<body name="human_torso" pos="{_vec(0, 0, s.lumbar_above_hip)}" gravcomp="1">',
        _inertial(p2, inertials, "torso"),
        *(_joint(p2, n) for n in ("trunk_flexion", "trunk_lateral_bend", "trunk_rotation")),
        _capsule(p2, "human_abdomen", (0, -0.5 * s.chest_half_width, 0.04 * h),
                 (0, 0.5 * s.chest_half_width, 0.04 * h), 0.06 * h, mat="human_cloth"),
        _capsule(p2, "human_spine", (0, 0, 0.04 * h), (0, 0, sh_z - 0.05 * h), 0.065 * h, mat="human_cloth"),
        _capsule(p2, "human_chest", (0, -0.75 * s.chest_half_width, sh_z - 0.045 * h),
                 (0, 0.75 * s.chest_half_width, sh_z - 0.045 * h), 0.06 * h, mat="human_cloth"),
        f'{p2}<body name="human_head" pos="{_vec(0, 0, s.lumbar_to_c7)}" gravcomp="1">',
        _inertial(p3, inertials, "head"),
        *(_joint(p3, n) for n in ("neck_flexion", "neck_lateral_bend", "neck_rotation")),
        # the neck rises straight from C7 and the skull sits on it (its centre over the neck, the face in
        # front): a flexed neck tips the head about C7 rather than hanging it out in front
        _capsule(p3, "human_neck", (0, 0, -0.01 * h), (0.004 * h, 0, 0.5 * s.c7_to_eye), 0.028 * h),
        _capsule(p3, "human_head", (0.008 * h, 0, s.c7_to_eye - 0.03 * h),
                 (0.008 * h, 0, s.c7_to_eye + s.head_top_above_eye - 0.055 * h), 0.055 * h),
        f'{p3}<site name="human_eyes" pos="{_vec(s.eye_forward, 0, s.c7_to_eye)}"/>',
        f"{p2}</body>",
        *_arm(s, "right", p2, inertials),
        *_arm(s, "left", p2, inertials),
        f"{p1}</body>",
        "      </body>",
        "    </body>",
        "  </worldbody>",
    ]
    if keyframe:
        # the key lists every joint in the order written above, which is the qpos order
        names = re.findall(r'<joint name="([^"]+)"', "\n".join(lines))
        qpos = [math.radians(HOME_POSTURE.get(n, 0.0)) for n in names]
        lines += ["", "  <keyframe>", f'    <key name="{keyframe}" qpos="{_vec(*qpos)}"/>', "  </keyframe>"]
    lines += ["</mujoco>", ""]
    return "\n".join(lines)
