"""Static scene geometry read from a compiled MjModel: per body, its visual geoms in the body frame.

The result is plain data (no rerun types), so what is drawn can be tested against the model directly.
Meshes loaded from a file (a robot's OBJ and STL files in ``models/<robot>/assets``) keep their file:
MuJoCo recentres and rotates mesh vertices at compile time (``mesh_pos``, ``mesh_quat``), so the pose of
the *file's* frame in the body is the geom pose composed with the inverse of that offset. Meshes without a
file (built from vertices in code) are taken from the compiled ``mesh_vert``/``mesh_face``, already in the
geom frame.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path

import mujoco
import numpy as np

from ergosim.errors import ModelError
from ergosim.viz.paths import GROUPS, body_entity

__all__ = ["Visual", "SceneBody", "VISIBLE_GROUPS", "scene_bodies", "default_body_groups"]

VISIBLE_GROUPS = (0, 1, 2)
"""Geom groups drawn, as MuJoCo's viewer shows them by default (group 3 holds the collision geoms)."""

_FILE_MESH_SUFFIXES = (".stl", ".obj")
_DEFAULT_RGBA = np.array([0.5, 0.5, 0.5, 1.0], dtype=np.float32)
_KINDS = {
    mujoco.mjtGeom.mjGEOM_SPHERE: "sphere",
    mujoco.mjtGeom.mjGEOM_CAPSULE: "capsule",
    mujoco.mjtGeom.mjGEOM_ELLIPSOID: "ellipsoid",
    mujoco.mjtGeom.mjGEOM_CYLINDER: "cylinder",
    mujoco.mjtGeom.mjGEOM_BOX: "box",
    mujoco.mjtGeom.mjGEOM_MESH: "mesh",
}


@dataclasses.dataclass(frozen=True, eq=False)
class Visual:
    """One drawable geom, posed in its body's frame.

    ``kind``: sphere | capsule | ellipsoid | cylinder | box | mesh. ``pos`` (3,) [m] and ``quat`` (4,) wxyz
    place the geom (for a file mesh: the file's frame) in the body frame. ``size`` (3,) is MuJoCo's
    ``geom_size`` [m] (radius, half-length / half-extents). ``rgba`` (4,) in 0..1. A mesh has either
    ``mesh_file`` (+ ``scale`` (3,)) or ``vertices`` (v, 3) [m] and ``faces`` (f, 3) int in the geom frame.
    ``geom`` is the MuJoCo geom id.
    """

    geom: int
    name: str
    kind: str
    pos: np.ndarray
    quat: np.ndarray
    size: np.ndarray
    rgba: np.ndarray
    mesh_file: Path | None = None
    scale: np.ndarray | None = None
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None


@dataclasses.dataclass(frozen=True, eq=False)
class SceneBody:
    """A body and its drawable geoms. ``static_pose`` is (pos (3,), quat wxyz (4,)) in the world frame for a
    body welded to the world (never moves, logged once), else None (its pose is logged per tick)."""

    id: int
    name: str
    group: str
    entity: str
    static_pose: tuple[np.ndarray, np.ndarray] | None
    visuals: tuple[Visual, ...]


def default_body_groups(model: mujoco.MjModel, parts: Sequence[str] = ()) -> dict[str, str]:
    """Groups by the workcells' make-up: ``human_*`` human, ``parts`` parts, a body whose tree from the
    world carries hinge or slide joints robot (whatever its model), else scene."""
    moving = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    arms = {int(model.body_rootid[model.jnt_bodyid[j]]) for j in range(model.njnt)
            if int(model.jnt_type[j]) in moving}
    groups = {}
    for b in range(1, model.nbody):
        name = model.body(b).name
        if name.startswith("human_"):
            groups[name] = "human"
        elif int(model.body_rootid[b]) in arms:
            groups[name] = "robot"
        elif name in parts:
            groups[name] = "parts"
        elif name:
            groups[name] = "scene"
    return groups


def scene_bodies(model: mujoco.MjModel, body_groups: Mapping[str, str],
                 groups: tuple[int, ...] = VISIBLE_GROUPS) -> tuple[SceneBody, ...]:
    """Every body of ``model`` with its visual geoms; bodies missing from ``body_groups`` are "scene".

    Raises ModelError for a ``body_groups`` entry that names no body or no known group, and when two
    bodies would share an entity path.
    """
    names = [model.body(b).name or f"body{b}" for b in range(model.nbody)]
    for body, group in body_groups.items():
        if body not in names:
            raise ModelError(f"body_groups names body {body!r}, which the model does not have",
                             where="ergosim.viz.log_static")
        if group not in GROUPS:
            raise ModelError(f"body {body!r} is in group {group!r}; expected one of {', '.join(GROUPS)}",
                             where="ergosim.viz.log_static")
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    by_body: list[list[Visual]] = [[] for _ in range(model.nbody)]
    for g in range(model.ngeom):
        visual = _visual(model, g, groups)
        if visual is not None:
            siblings = by_body[model.geom_bodyid[g]]
            if any(v.name == visual.name for v in siblings):  # names become entity paths: keep them unique
                visual = dataclasses.replace(visual, name=f"{visual.name}_{g}")
            siblings.append(visual)
    bodies, seen = [], {}
    for b, name in enumerate(names):
        group = body_groups.get(name, "scene")
        entity = body_entity(group, name)
        if entity in seen:
            raise ModelError(f"bodies {seen[entity]!r} and {name!r} would both be drawn at {entity}",
                             where="ergosim.viz.log_static")
        seen[entity] = name
        static = b == 0 or (model.body_weldid[b] == 0 and model.body_mocapid[b] < 0)
        pose = (data.xpos[b].copy(), data.xquat[b].copy()) if static else None
        bodies.append(SceneBody(b, name, group, entity, pose, tuple(by_body[b])))
    return tuple(bodies)


def _visual(model: mujoco.MjModel, g: int, groups: tuple[int, ...]) -> Visual | None:
    kind = _KINDS.get(mujoco.mjtGeom(model.geom_type[g]))
    rgba = _rgba(model, g)
    if kind is None or model.geom_group[g] not in groups or rgba[3] <= 0.0:
        return None
    name = model.geom(g).name
    if not name and kind == "mesh":
        name = model.mesh(model.geom_dataid[g]).name
    name = name or f"geom{g}"
    pos, quat = model.geom_pos[g].copy(), model.geom_quat[g].copy()
    size = model.geom_size[g].copy()
    if kind != "mesh":
        return Visual(g, name, kind, pos, quat, size, rgba)
    m = model.geom_dataid[g]
    path = _mesh_path(model, m)
    if path is not None:
        # compiled vertex = R(mesh_quat)^T (scale * file vertex - mesh_pos): undo it on the geom side
        inv = np.empty(4)
        mujoco.mju_negQuat(inv, model.mesh_quat[m])
        offset = np.empty(3)
        mujoco.mju_rotVecQuat(offset, -model.mesh_pos[m], inv)
        file_pos, file_quat = np.empty(3), np.empty(4)
        mujoco.mju_rotVecQuat(file_pos, offset, quat)
        mujoco.mju_mulQuat(file_quat, quat, inv)
        return Visual(g, name, kind, pos + file_pos, file_quat, size, rgba, mesh_file=path,
                      scale=model.mesh_scale[m].copy())
    v0, nv = model.mesh_vertadr[m], model.mesh_vertnum[m]
    f0, nf = model.mesh_faceadr[m], model.mesh_facenum[m]
    return Visual(g, name, kind, pos, quat, size, rgba, vertices=model.mesh_vert[v0:v0 + nv].copy(),
                  faces=model.mesh_face[f0:f0 + nf].copy())


def _rgba(model: mujoco.MjModel, g: int) -> np.ndarray:
    """The colour MuJoCo draws: the material's unless the geom sets its own (non-default) rgba."""
    rgba = model.geom_rgba[g].astype(np.float32)
    mat = model.geom_matid[g]
    if mat >= 0 and np.array_equal(rgba, _DEFAULT_RGBA):
        rgba = model.mat_rgba[mat].astype(np.float32)
    return rgba


def _mesh_path(model: mujoco.MjModel, m: int) -> Path | None:
    """The mesh's source file, if it is one rerun can load and it still exists."""
    adr = model.mesh_pathadr[m]
    if adr < 0:
        return None
    raw = model.paths[adr:].split(b"\0", 1)[0].decode()
    path = Path(raw)
    if not raw or path.suffix.lower() not in _FILE_MESH_SUFFIXES or not path.is_file():
        return None
    return path
