"""Part meshes: binary or ASCII STL and Wavefront OBJ, read through trimesh.

A binary STL goes to MuJoCo as the file it is (MuJoCo reads binary STL itself, so a cell with one builds as
it always did, bit for bit). An ASCII STL or an OBJ, which MuJoCo cannot read, is read by trimesh and given
to MuJoCo as its vertices and triangles (``uservert``/``userface`` of the MjSpec mesh): nothing is written to
disk, so there is no temporary file to clean up, and an exported scene (:mod:`ergosim.scenes.export`) carries
the mesh inside its MJCF.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError

__all__ = ["MESH_SUFFIXES", "MAX_MESH_TRIANGLES", "is_binary_stl", "mesh_triangles", "read_mesh"]

MESH_SUFFIXES = (".stl", ".obj")
"""The mesh files a part may name."""
MAX_MESH_TRIANGLES = 50_000
"""Most triangles of a part's mesh (assumed: the bundled robot meshes have at most 1,176; a 199,000-
triangle STL, under MuJoCo's cap of 200,000, kept the build busy past 240 s)."""


def is_binary_stl(path: Path) -> bool:
    """Whether ``path`` is a binary STL: its size is that of the triangle count in bytes 80-84."""
    if path.suffix.lower() != ".stl":
        return False
    with path.open("rb") as f:
        head = f.read(84)
    return len(head) == 84 and path.stat().st_size == 84 + 50 * int.from_bytes(head[80:84], "little")


def mesh_triangles(path: Path) -> int:
    """Triangles of the mesh file at ``path``, counted without parsing it: a binary STL's count, an ASCII
    STL's facets, an OBJ's faces (a polygon of n corners counted as its n - 2 triangles)."""
    if is_binary_stl(path):
        with path.open("rb") as f:
            return int.from_bytes(f.read(84)[80:84], "little")
    data = path.read_bytes()
    if path.suffix.lower() == ".stl":
        return data.count(b"endfacet")
    return sum(max(len(line.split()) - 3, 1) for line in data.splitlines() if line.startswith(b"f "))


def read_mesh(path: Path, where: str) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3) [file units], triangles (m, 3) vertex indices) of the mesh at ``path``; a file trimesh
    cannot read, or one with no triangle, is a :class:`ConfigError` at ``where``."""
    import trimesh  # noqa: PLC0415 - 0.7 s to import, paid only by a cell with such a mesh

    kind = path.suffix.lower().lstrip(".")
    try:
        mesh = trimesh.load(str(path), file_type=kind, force="mesh", process=False)
        vertices = np.asarray(mesh.vertices, dtype=float)
        faces = np.asarray(mesh.faces, dtype=np.int64)
    except Exception as err:  # noqa: BLE001 - trimesh's readers raise many kinds; each is one message here
        text = str(err).splitlines()[0] if str(err) else type(err).__name__
        raise ConfigError(f"cannot read the mesh file {str(path)!r}: {text}", where=where) from None
    if faces.ndim != 2 or faces.shape[1:] != (3,) or len(faces) == 0 or not np.all(np.isfinite(vertices)):
        raise ConfigError(f"the mesh file {str(path)!r} holds no triangles with finite vertices (is it an "
                          f"{kind.upper()} file?)", where=where)
    if len(faces) > MAX_MESH_TRIANGLES:
        raise ConfigError(f"{str(path)!r} has {len(faces)} triangles, more than the limit of "
                          f"{MAX_MESH_TRIANGLES} (ergosim.scenes.meshes.MAX_MESH_TRIANGLES; simplify the "
                          "mesh)", where=where)
    return vertices, faces
