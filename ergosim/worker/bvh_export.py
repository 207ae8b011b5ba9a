"""The project's BVH exporter: canonical angle trajectories -> a BVH file with the project's own skeleton.

The skeleton (:func:`export_skeleton`) has the joint centres of the human model
(:func:`ergosim.human.anthropometry.segment_lengths`): Y up, the figure facing +Z (+X is its left),
centimetres, T-pose rest (arms along the segment axes, palms down), Euler channels ``Zrotation Xrotation
Yrotation`` on every joint, root position channels holding the pelvis at hip height. Each segment's
anatomical orientation comes from the canonical angles along the human model's chains; its BVH rotation is
the same orientation expressed relative to the T-pose rest.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ergosim.errors import RecordingError
from ergosim.human.anthropometry import segment_lengths
from ergosim.posture import HUMAN_JOINTS
from ergosim.worker.bvh_euler import matrix_to_euler
from ergosim.worker.bvh_mapping import angles_to_frames, map_skeleton
from ergosim.worker.bvh_parse import BvhData, BvhJoint

__all__ = ["EXPORT_ORDER", "export_skeleton", "format_bvh", "bvh_text"]

EXPORT_ORDER = "ZXY"
_ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation")
_ROT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
# Body (x forward, y left, z up) -> file axes: Y up, the figure faces +Z, +X is its left.
_FILE_FROM_BODY = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
_EXPORT_ROLES = {"Spine": "thorax", "Neck": "head", "RightShoulder": "right_clavicle",
                 "RightArm": "right_upper_arm", "RightForeArm": "right_forearm", "RightHand": "right_hand",
                 "LeftShoulder": "left_clavicle", "LeftArm": "left_upper_arm", "LeftForeArm": "left_forearm",
                 "LeftHand": "left_hand"}


def _num(x: float) -> str:
    s = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _fmt(xs) -> str:
    return " ".join(_num(float(x)) for x in xs)


def format_bvh(joints: tuple[BvhJoint, ...] | list[BvhJoint], frame_time: float, motion: np.ndarray) -> str:
    """BVH text of a skeleton (depth-first ``joints``) and its (n_frames, n_channels) ``motion``."""
    out = ["HIERARCHY"]

    def emit(i: int, depth: int) -> None:
        j, pad = joints[i], "  " * depth
        out.append(f"{pad}{'ROOT' if j.parent < 0 else 'JOINT'} {j.name}")
        out.append(f"{pad}{{")
        out.append(f"{pad}  OFFSET {_fmt(j.offset)}")
        out.append(f"{pad}  CHANNELS {len(j.channels)} {' '.join(j.channels)}".rstrip())
        for k, c in enumerate(joints):
            if c.parent == i:
                emit(k, depth + 1)
        if j.end_site is not None:
            out.extend([f"{pad}  End Site", f"{pad}  {{", f"{pad}    OFFSET {_fmt(j.end_site)}",
                        f"{pad}  }}"])
        out.append(f"{pad}}}")

    emit(0, 0)
    out += ["MOTION", f"Frames: {motion.shape[0]}", f"Frame Time: {frame_time:.9f}"]
    out += [" ".join(f"{x:.6f}" for x in row) for row in np.asarray(motion, dtype=float)]
    return "\n".join(out) + "\n"



def _joint(name, parent, offset_body, channels, end_site_body=None) -> BvhJoint:
    def cm(v):
        return tuple(float(x) for x in 100.0 * _FILE_FROM_BODY @ np.asarray(v, dtype=float))
    return BvhJoint(name, parent, cm(offset_body), channels, 0, None if end_site_body is None else
                    cm(end_site_body), 0)


def export_skeleton(stature: float = 1.75) -> tuple[BvhJoint, ...]:
    """The exported skeleton for ``stature`` [m]: joints in depth-first order, offsets in cm, T-pose rest.

    Hips (root, at hip height) -> Spine (L5/S1: trunk angles) -> Neck (C7: neck angles) -> Head; Spine ->
    Right/LeftShoulder (sternoclavicular joint: elevation) -> Arm (glenohumeral) -> ForeArm (elbow) -> Hand
    (wrist); Hips -> Right/LeftUpLeg -> Leg -> Foot (static). Same joint centres as the human model.
    """
    s = segment_lengths(stature)
    joints: list[BvhJoint] = []

    def add(name, parent, offset, channels=_ROT_CHANNELS, end=None) -> int:
        joints.append(_joint(name, parent, offset, channels, end))
        return len(joints) - 1

    hips = add("Hips", -1, (0, 0, 0), _ROOT_CHANNELS)
    spine = add("Spine", hips, (0, 0, s.lumbar_above_hip))
    neck = add("Neck", spine, (0, 0, s.lumbar_to_c7))
    add("Head", neck, (0, 0, 0.5 * s.c7_to_eye), end=(0, 0, 0.5 * s.c7_to_eye + s.head_top_above_eye))
    sc_z = s.lumbar_to_c7 - s.c7_to_shoulder - s.sc_below
    for side, y in (("Right", -1.0), ("Left", 1.0)):
        clav = add(f"{side}Shoulder", spine, (s.sc_forward, y * s.sc_lateral, sc_z))
        arm = add(f"{side}Arm", clav, (-s.sc_forward, y * (s.shoulder_half_width - s.sc_lateral), s.sc_below))
        fore = add(f"{side}ForeArm", arm, (0, y * s.upper_arm, 0))
        add(f"{side}Hand", fore, (0, y * s.forearm, 0), end=(0, y * s.hand, 0))
    for side, y in (("Right", -1.0), ("Left", 1.0)):
        up = add(f"{side}UpLeg", hips, (0, y * 0.55 * s.hip_half_width, 0))
        leg = add(f"{side}Leg", up, (0, 0, -s.thigh))
        add(f"{side}Foot", leg, (0, 0, -s.shank), end=(0.7 * s.foot, 0, 0))
    first, out = 0, []
    for j in joints:  # channel columns in depth-first (file) order
        out.append(BvhJoint(j.name, j.parent, j.offset, j.channels, first, j.end_site, 0))
        first += len(j.channels)
    return tuple(out)


def _angle_columns(angles: Mapping[str, np.ndarray | float]) -> tuple[dict[str, np.ndarray], int]:
    unknown = sorted(set(angles) - set(HUMAN_JOINTS))
    if unknown:
        raise RecordingError(f"unknown angle names {', '.join(unknown)}; expected names of "
                             "ergosim.posture.HUMAN_JOINTS", where="save_bvh")
    cols = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in angles.items()}
    n = max((c.shape[0] for c in cols.values()), default=1)
    for k, c in cols.items():
        if c.ndim != 1 or c.shape[0] not in (1, n):
            raise RecordingError(f"angle {k!r} has shape {c.shape}, expected ({n},)", where="save_bvh")
        if not np.all(np.isfinite(c)):
            raise RecordingError(f"angle {k!r} has NaN or infinite frames; BVH has no dropouts, fill them "
                                 "first", where="save_bvh")
    return {k: np.broadcast_to(c, (n,)) for k, c in cols.items()}, n


def bvh_text(angles: Mapping[str, np.ndarray | float], rate_hz: float, stature: float = 1.75) -> str:
    """BVH text of canonical ``angles`` (name -> (n,) or scalar [deg]; missing names are 0) at ``rate_hz``."""
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise RecordingError(f"rate must be a positive number of Hz, got {rate_hz}", where="save_bvh")
    cols, n = _angle_columns(angles)
    joints = export_skeleton(stature)
    seg = angles_to_frames(cols, n)
    smap = map_skeleton(BvhData(joints, 1.0 / rate_hz, np.zeros((1, 0)), "export skeleton"))
    c = smap.c
    world = {j.name: None for j in joints}  # file-axes world rotation of each joint, None = identity
    motion = np.zeros((n, sum(len(j.channels) for j in joints)))
    for j in joints:
        parent = world[joints[j.parent].name] if j.parent >= 0 else None
        role = _EXPORT_ROLES.get(j.name)
        if role is None:
            world[j.name] = parent
            continue
        g = c.T @ seg[role] @ smap.rest[role].T @ c
        world[j.name] = g
        local = g if parent is None else np.swapaxes(parent, -1, -2) @ g
        motion[:, j.first_channel:j.first_channel + 3] = np.rad2deg(matrix_to_euler(local, EXPORT_ORDER))
    motion[:, 1] = 100.0 * segment_lengths(stature).hip_height  # root Yposition: pelvis at hip height
    return format_bvh(joints, 1.0 / rate_hz, motion)
