"""Map a BVH skeleton onto the canonical angles of :mod:`ergosim.posture`.

Three steps, documented with the mapping table in docs/bvh.md:

1. **Roles.** Each body segment the canonical angles need (pelvis, thorax, head, and per side clavicle,
   upper arm, forearm, hand) is a BVH joint, found by name (Xsens MVN, generic/Vicon/CMU/Mixamo/Motive,
   Poser and DAZ-friendly spellings, case-insensitive, namespace prefixes ``ns:`` ignored) or given by the
   user. The thorax is the joint the clavicle (or, without one, the upper arm) hangs from.
2. **Body frame.** The file's axes are related to the body frame (x forward, y left, z up) from the rest
   pose: up is pelvis -> head, left is right shoulder -> left shoulder, each snapped to the nearest file
   axis when within 20 deg (BVH files are Y-up or Z-up with the figure facing an axis).
3. **Rest pose.** A BVH rest pose (all channels zero) is usually a T-pose, not the anatomical neutral of
   posture.py (arms hanging, palms in). Each arm segment's rest orientation relative to neutral is the
   smallest rotation that turns the neutral bone direction (-z, hanging) into the rest bone direction
   (towards the next joint); a T-pose therefore reads shoulder_abduction = 90 deg with palms down. The
   hand is assumed aligned with the forearm at rest; trunk, head and clavicles are assumed neutral.

Then every segment's anatomical orientation is ``A = C G C^T R_rest`` (G: the joint's world rotation in
the file's axes, C: file -> body axes), and the canonical angles are the decompositions of the relative
orientations along the chains of :mod:`ergosim.worker.bvh_chains`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ergosim.errors import RecordingError
from ergosim.worker.bvh_chains import CHAINS, HeldFrame, compose, decompose
from ergosim.worker.bvh_kinematics import global_rotations
from ergosim.worker.bvh_parse import BvhData
from ergosim.worker.bvh_products import const_times, times_const

__all__ = ["ROLES", "REQUIRED_ROLES", "NAME_CANDIDATES", "SkeletonMap", "map_skeleton", "segment_frames",
           "frames_to_angles", "angles_to_frames", "recording_angles", "TRUNK_REFERENCES"]

SIDES = {"right": "", "left": "left_"}
ARM_SEGMENTS = ("clavicle", "upper_arm", "forearm", "hand")
ROLES = ("pelvis", "thorax", "head") + tuple(f"{s}_{g}" for s in SIDES for g in ARM_SEGMENTS)
REQUIRED_ROLES = ("pelvis", "thorax", "head", "right_upper_arm", "right_forearm", "right_hand")
TRUNK_REFERENCES = ("vertical", "pelvis")

_RIGHT_NAMES = {
    # Xsens MVN; generic/Vicon/CMU/Mixamo/Motive; Poser; DAZ-friendly (rcollar, rshoulder, relbow, rhand).
    "clavicle": ("RightShoulder", "RightCollar", "RightClavicle", "rCollar"),
    "upper_arm": ("RightUpperArm", "RightArm", "rShldr", "rShoulder"),
    "forearm": ("RightForeArm", "RightLowerArm", "rForeArm", "rElbow"),
    "hand": ("RightHand", "rHand"),
}


def _left(name: str) -> str:
    return "Left" + name[5:] if name.startswith("Right") else ("l" if name[0] == "r" else "L") + name[1:]


NAME_CANDIDATES: dict[str, tuple[str, ...]] = {
    "pelvis": ("Pelvis", "Hips", "Hip"),
    "head": ("Head",),
    **{f"right_{g}": names for g, names in _RIGHT_NAMES.items()},
    **{f"left_{g}": tuple(_left(n) for n in names) for g, names in _RIGHT_NAMES.items()},
}
"""Joint names tried for each role, in order (the thorax is found structurally, see the module doc)."""

_SNAP_COS = np.cos(np.deg2rad(20.0))
_CHUNK = 8192  # frames per batch, bounds the (n, 3, 3) temporaries of long recordings


@dataclass(frozen=True, eq=False)
class SkeletonMap:
    """Roles of a parsed skeleton: role -> joint index, file -> body axes ``c`` (3, 3), rest rotations."""

    joints: Mapping[str, int]
    names: Mapping[str, str]
    c: np.ndarray
    rest: Mapping[str, np.ndarray]


def _norm(name: str) -> str:
    return name.rsplit(":", 1)[-1].lower()


def _find(data: BvhData, role: str) -> int | None:
    names = [_norm(j.name) for j in data.joints]
    for cand in NAME_CANDIDATES[role]:
        if cand.lower() in names:
            return names.index(cand.lower())
    if role != "pelvis":  # asset prefixes such as "Skeleton1_RHand"
        for cand in NAME_CANDIDATES[role]:
            hit = [k for k, n in enumerate(names) if n.endswith("_" + cand.lower())]
            if len(hit) == 1:
                return hit[0]
    return None


def _ancestors(data: BvhData, i: int) -> list[int]:
    out = []
    while data.joints[i].parent >= 0:
        i = data.joints[i].parent
        out.append(i)
    return out


def _rest_positions(data: BvhData) -> np.ndarray:
    pos = np.zeros((len(data.joints), 3))
    for i, j in enumerate(data.joints):
        pos[i] = j.offset if j.parent < 0 else pos[j.parent] + np.asarray(j.offset)
    return pos


def _unit(v: np.ndarray, what: str, where: str) -> np.ndarray:
    n = np.linalg.norm(v)
    if n < 1e-9:
        raise RecordingError(f"cannot tell the body's {what} from the rest pose (zero-length bone)",
                             where=where)
    return v / n


def _snap(v: np.ndarray) -> np.ndarray:
    k = int(np.argmax(np.abs(v)))
    if abs(v[k]) >= _SNAP_COS:
        out = np.zeros(3)
        out[k] = np.sign(v[k])
        return out
    return v


def _min_rotation(d: np.ndarray, where: str, role: str) -> np.ndarray:
    """Smallest rotation turning the hanging direction (0, 0, -1) into the unit direction ``d``."""
    n = np.array([0.0, 0.0, -1.0])
    c = float(n @ d)
    if c < -0.95:
        raise RecordingError(f"the {role.replace('_', ' ')} points upwards in the rest pose; expected a T-, "
                             "A- or N-pose", where=where)
    v = np.cross(n, d)
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


def _resolve(data: BvhData, name_map: Mapping[str, str] | None) -> dict[str, int]:
    where = data.source
    roles: dict[str, int] = {}
    for role, name in (name_map or {}).items():
        if role not in ROLES:
            raise RecordingError(f"unknown role {role!r} in the name map; expected one of {', '.join(ROLES)}",
                                 where=where)
        try:
            roles[role] = data.index(name)
        except KeyError:
            raise RecordingError(f"the name map puts {role} on joint {name!r}, which the file does not have",
                                 where=where) from None
    for role in NAME_CANDIDATES:
        if role not in roles and (k := _find(data, role)) is not None:
            roles[role] = k
    roles.setdefault("pelvis", 0)
    if "thorax" not in roles:
        top = roles.get("right_clavicle", roles.get("right_upper_arm"))
        if top is not None and data.joints[top].parent >= 0:
            roles["thorax"] = data.joints[top].parent
    missing = [r for r in REQUIRED_ROLES if r not in roles]
    if missing:
        raise RecordingError(f"no joint found for {', '.join(missing)}; pass a name map "
                             "(role -> joint name), see docs/bvh.md", where=where)
    left = [r for r in roles if r.startswith("left_")]
    if left and not all(f"left_{g}" in roles for g in ARM_SEGMENTS[1:]):
        for r in left:  # an incomplete left arm is ignored rather than half-mapped
            del roles[r]
    chain = ("pelvis", "thorax", "{s}clavicle", "{s}upper_arm", "{s}forearm", "{s}hand")
    for side in ("right_", "left_"):
        present = [r.format(s=side) for r in chain if r.format(s=side) in roles]
        for parent, child in zip(present, present[1:], strict=False):
            if roles[parent] not in _ancestors(data, roles[child]):
                raise RecordingError(f"joint {data.joints[roles[child]].name!r} ({child}) is not below "
                                     f"{data.joints[roles[parent]].name!r} ({parent}) in the hierarchy",
                                     where=where)
    if roles["thorax"] not in _ancestors(data, roles["head"]):
        raise RecordingError(f"joint {data.joints[roles['head']].name!r} (head) is not below the thorax "
                             f"{data.joints[roles['thorax']].name!r}", where=where)
    return {r: roles[r] for r in ROLES if r in roles}


def map_skeleton(data: BvhData, name_map: Mapping[str, str] | None = None) -> SkeletonMap:
    """Roles, body axes and rest-pose corrections of ``data``'s skeleton (see the module doc)."""
    roles = _resolve(data, name_map)
    where = data.source
    pos = _rest_positions(data)
    up = _snap(_unit(pos[roles["head"]] - pos[roles["pelvis"]], "up direction", where))
    right_sh = pos[roles["right_upper_arm"]]
    lateral = (pos[roles["left_upper_arm"]] if "left_upper_arm" in roles else pos[roles["thorax"]]) - right_sh
    left = _snap(_unit(lateral - (lateral @ up) * up, "left direction", where))
    c = np.stack([np.cross(left, up), left, up])  # rows: body x, y, z in file axes
    rest = {r: np.eye(3) for r in roles}
    for side in SIDES:
        if f"{side}_upper_arm" not in roles:
            continue
        for seg, nxt in (("upper_arm", "forearm"), ("forearm", "hand")):
            a, b = roles[f"{side}_{seg}"], roles[f"{side}_{nxt}"]
            d = _unit(c @ (pos[b] - pos[a]), f"{side} {seg.replace('_', ' ')} direction", where)
            rest[f"{side}_{seg}"] = _min_rotation(d, where, f"{side}_{seg}")
        rest[f"{side}_hand"] = rest[f"{side}_forearm"]
    names = {r: data.joints[k].name for r, k in roles.items()}
    return SkeletonMap(roles, names, c, rest)


def segment_frames(data: BvhData, smap: SkeletonMap,
                   frames: slice | np.ndarray = slice(None)) -> dict[str, np.ndarray]:
    """Anatomical orientation (n, 3, 3) of each mapped segment in body axes (identity = neutral posture), for
    the ``frames`` (a slice or indices) of ``data``."""
    g = global_rotations(data, list(smap.joints.values()), frames)
    return {r: times_const(times_const(const_times(smap.c, g[k]), smap.c.T), smap.rest[r])
            for r, k in smap.joints.items()}


def _heading(a_pelvis: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation about the vertical by the pelvis's heading (its forward axis on the floor)."""
    fwd = a_pelvis[:, :, 0]
    psi = np.arctan2(fwd[:, 1], fwd[:, 0])
    c, s = np.cos(psi), np.sin(psi)
    r = np.zeros((len(psi), 3, 3))
    r[:, 0, 0], r[:, 0, 1], r[:, 1, 0], r[:, 1, 1], r[:, 2, 2] = c, -s, s, c, 1.0
    return r


def _rel(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.swapaxes(a, -1, -2) @ b


def frames_to_angles(seg: Mapping[str, np.ndarray], trunk_reference: str = "vertical",
                     consecutive: bool = True) -> dict[str, np.ndarray]:
    """Canonical angles [deg], name -> (n,), from segment orientations (see :func:`segment_frames`).

    ``trunk_reference="vertical"`` measures the trunk against the upright with the pelvis's heading (hip
    flexion counts as trunk flexion, as in the human model whose pelvis is fixed and as RULA scores it);
    ``"pelvis"`` measures it against the pelvis segment (lumbar spine only). ``consecutive``: False for a
    sample of a recording's frames (:func:`~ergosim.worker.bvh_chains.decompose`).
    """
    if trunk_reference not in TRUNK_REFERENCES:
        raise ValueError(f"trunk_reference must be one of {TRUNK_REFERENCES}, not {trunk_reference!r}")
    def dec(chain: str, r: np.ndarray, pre: str = "") -> dict[str, np.ndarray]:
        return decompose(CHAINS[chain], r, pre, consecutive)

    thorax = seg["thorax"]
    ref = _heading(seg["pelvis"]) if trunk_reference == "vertical" else seg["pelvis"]
    out = dec("trunk", _rel(ref, thorax))
    out |= dec("neck", _rel(thorax, seg["head"]))
    for side, pre in SIDES.items():
        if f"{side}_upper_arm" not in seg:
            continue
        clav = thorax
        if f"{side}_clavicle" in seg:
            out |= dec("clavicle", _rel(thorax, seg[f"{side}_clavicle"]), pre)
            # Only the elevation is a canonical angle: the arm hangs from a clavicle that only elevates, so
            # any protraction or twist of the recorded clavicle is counted in the shoulder angles.
            clav = thorax @ compose(CHAINS["clavicle"], out, pre)
        else:
            out[pre + "shoulder_elevation"] = np.zeros(len(thorax))
        upper, fore = seg[f"{side}_upper_arm"], seg[f"{side}_forearm"]
        out |= dec("shoulder", _rel(clav, upper), pre)
        out |= dec("elbow", _rel(upper, fore), pre)
        out |= dec("wrist", _rel(fore, seg[f"{side}_hand"]), pre)
    return out


def angles_to_frames(angles: Mapping[str, np.ndarray | float], n: int) -> dict[str, np.ndarray]:
    """Inverse of :func:`frames_to_angles` for a fixed upright pelvis: segment orientations (n, 3, 3)."""
    def rot(chain: str, pre: str = "") -> np.ndarray:
        return np.broadcast_to(compose(CHAINS[chain], angles, pre), (n, 3, 3))

    seg = {"pelvis": np.broadcast_to(np.eye(3), (n, 3, 3)), "thorax": rot("trunk")}
    seg["head"] = seg["thorax"] @ rot("neck")
    for side, pre in SIDES.items():
        seg[f"{side}_clavicle"] = seg["thorax"] @ rot("clavicle", pre)
        seg[f"{side}_upper_arm"] = seg[f"{side}_clavicle"] @ rot("shoulder", pre)
        seg[f"{side}_forearm"] = seg[f"{side}_upper_arm"] @ rot("elbow", pre)
        seg[f"{side}_hand"] = seg[f"{side}_forearm"] @ rot("wrist", pre)
    return seg


def recording_angles(data: BvhData, smap: SkeletonMap, trunk_reference: str = "vertical",
                     frames: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Canonical angles [deg], name -> (n_frames,), of every frame of ``data``, in batches of frames.

    ``frames``: increasing indices of the only frames to map, e.g. the ones a replay's ticks use; each gets
    the angles of the whole mapping bit for bit (a batch where such a frame is in gimbal lock is mapped
    whole, as it holds an angle of the frame before). The result is then name -> (len(frames),).
    """
    if frames is None:
        parts = [frames_to_angles(segment_frames(data, smap, slice(a, a + _CHUNK)), trunk_reference)
                 for a in range(0, data.n_frames, _CHUNK)]
        return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    frames = np.asarray(frames, dtype=np.int64)
    parts = [frames_to_angles(segment_frames(data, smap, frames[:0]), trunk_reference)]
    for a in range(0, data.n_frames, _CHUNK):
        lo, hi = np.searchsorted(frames, (a, a + _CHUNK))
        if lo == hi:
            continue
        try:
            part = frames_to_angles(segment_frames(data, smap, frames[lo:hi]), trunk_reference, False)
        except HeldFrame:
            whole = frames_to_angles(segment_frames(data, smap, slice(a, a + _CHUNK)), trunk_reference)
            part = {k: v[frames[lo:hi] - a] for k, v in whole.items()}
        parts.append(part)
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
