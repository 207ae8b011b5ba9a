"""Log the static scene (from :mod:`ergosim.viz.geometry`) as rerun archetypes, once per recording.

Each body is an entity ``world/<group>/<body>`` carrying its world pose; its primitive geoms are batched
per shape (``.../boxes``, ``.../capsules``...) with per-instance poses in the body frame, and each mesh is a
child entity with a static body-frame transform.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import rerun as rr

from ergosim.quat import wxyz_to_xyzw
from ergosim.viz.geometry import SceneBody, Visual
from ergosim.viz.paths import join

__all__ = ["log_scene"]

_PRIMITIVE_ENTITY = {"box": "boxes", "sphere": "spheres", "ellipsoid": "ellipsoids", "capsule": "capsules",
                     "cylinder": "cylinders"}


def log_scene(stream: rr.RecordingStream, bodies: Sequence[SceneBody]) -> None:
    """Static transforms of world-welded bodies and every body's geometry."""
    for body in bodies:
        if body.static_pose is not None:
            pos, quat = body.static_pose
            pose = rr.Transform3D(translation=pos, quaternion=wxyz_to_xyzw(quat))
            stream.log(body.entity, pose, static=True)
        for kind, entity in _PRIMITIVE_ENTITY.items():
            visuals = [v for v in body.visuals if v.kind == kind]
            if visuals:
                stream.log(join(body.entity, entity), _primitives(kind, visuals), static=True)
        for v in body.visuals:
            if v.kind == "mesh":
                entity = join(body.entity, v.name)
                stream.log(entity, rr.Transform3D(translation=v.pos, quaternion=wxyz_to_xyzw(v.quat),
                                                  scale=v.scale), static=True)
                stream.log(entity, _mesh(v), static=True)


def _colors(visuals: Sequence[Visual]) -> np.ndarray:
    return np.round(np.array([v.rgba for v in visuals]) * 255).astype(np.uint8)


def _primitives(kind: str, visuals: Sequence[Visual]) -> rr.AsComponents:
    pos = np.array([v.pos for v in visuals])
    quat = wxyz_to_xyzw(np.array([v.quat for v in visuals]))
    size = np.array([v.size for v in visuals])
    colors = _colors(visuals)
    labels = [v.name for v in visuals]
    if kind == "box":
        return rr.Boxes3D(half_sizes=size, centers=pos, quaternions=quat, colors=colors, labels=labels,
                          show_labels=False, fill_mode="solid")
    if kind in ("sphere", "ellipsoid"):
        half = np.repeat(size[:, :1], 3, axis=1) if kind == "sphere" else size
        return rr.Ellipsoids3D(half_sizes=half, centers=pos, quaternions=quat, colors=colors, labels=labels,
                               show_labels=False, fill_mode="solid")
    if kind == "cylinder":
        return rr.Cylinders3D(lengths=2 * size[:, 1], radii=size[:, 0], centers=pos, quaternions=quat,
                              colors=colors, labels=labels, show_labels=False, fill_mode="solid")
    # MuJoCo's capsule is centred on the geom; rerun's starts at the origin and runs along +z
    start = np.empty_like(pos)
    for i, v in enumerate(visuals):
        mujoco.mju_rotVecQuat(start[i], np.array([0.0, 0.0, -v.size[1]]), v.quat)
    return rr.Capsules3D(lengths=2 * size[:, 1], radii=size[:, 0], translations=pos + start, quaternions=quat,
                         colors=colors, labels=labels, show_labels=False, fill_mode="solid")


def _mesh(v: Visual) -> rr.AsComponents:
    color = _colors([v])[0]
    if v.mesh_file is not None:
        return rr.Asset3D(path=v.mesh_file, albedo_factor=color)
    # flat-shaded: one vertex per face corner, so every triangle gets its own normal
    corners = v.vertices[v.faces].astype(np.float32)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    return rr.Mesh3D(vertex_positions=corners.reshape(-1, 3), vertex_normals=np.repeat(normals, 3, axis=0),
                     albedo_factor=color)
