"""Fewer triangles for a robot's visual meshes (the ``visual`` class, group 2), never its collision ones.

A software rasteriser (Mesa llvmpipe) pays for every triangle in each of the passes a shadowed frame takes,
so the Panda's 134,300 visual triangles cost more than half of a video frame (docs/video.md). Quadric
edge-collapse decimation (Garland & Heckbert 1997; trimesh's ``simplify_quadric_decimation``, backed by
the ``fast-simplification`` package) keeps the silhouette and the large flat faces and drops the fine
tessellation of the curved casings, which a 960x540 frame cannot show. The trimesh package welds the
COLLADA triangles into a connected mesh first. (Keeping each part's border, fast-simplification's
``preserve_border``, was tried: with the seams fixed the few triangles left inside stretch, and the white
casing shows through the black rings in a close view.)

Collision geoms and inertias are not read from these meshes (the visual class has no contacts and zero
density), so decimating them cannot change a simulation.
"""

from __future__ import annotations

import numpy as np

from ergosim.robot.collada import ColouredMesh

__all__ = ["decimate", "target_faces"]


def target_faces(faces: int, keep: float, floor: int) -> int:
    """Triangles to keep of a part of ``faces``: the fraction ``keep``, but never fewer than ``floor``
    (small parts, such as screw heads and labels, stay as they are)."""
    if not 0.0 < keep <= 1.0:
        raise ValueError(f"keep must be in (0, 1], got {keep}")
    return min(faces, max(floor, round(faces * keep)))


def decimate(mesh: ColouredMesh, keep: float, floor: int = 200) -> ColouredMesh:
    """``mesh`` with about ``target_faces(len(mesh.faces), keep, floor)`` triangles, same colour; ``mesh``
    itself when nothing is to be removed. Vertices [m] stay in the mesh's frame. Deterministic: the same
    input gives the same triangles (the committed models are compared with the generator byte for byte)."""
    target = target_faces(len(mesh.faces), keep, floor)
    if target >= len(mesh.faces):
        return mesh
    import fast_simplification  # noqa: PLC0415 - only the model generator needs these
    import trimesh  # noqa: PLC0415

    # process=True welds duplicate vertices first, so edges shared by two triangles can collapse
    tm = trimesh.Trimesh(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces), process=True)
    vertices, faces = fast_simplification.simplify(np.asarray(tm.vertices, dtype=float),
                                                   np.asarray(tm.faces, dtype=np.int32), target_count=target)
    return ColouredMesh(np.asarray(vertices, dtype=float), np.asarray(faces, dtype=np.int64), mesh.rgba)
