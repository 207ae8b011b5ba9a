"""Read the triangle meshes and colours of a COLLADA (.dae) file, for converting robot visuals to OBJ.

MuJoCo reads STL, OBJ and MSH but no COLLADA, while the URDFs of example-robot-data give their visual
meshes as .dae. This reader takes what a visual needs and nothing more: every ``<triangles>`` (and
triangulated ``<polylist>``) of every geometry instanced by the visual scene, placed by its node
transforms (``matrix``, ``translate``, ``rotate``, ``scale``) and the asset's unit and up axis, grouped by
the diffuse colour of its material. Textures are not read (the robots' meshes carry none).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ergosim.errors import ModelError

__all__ = ["ColouredMesh", "read_collada"]

_NS = {"c": "http://www.collada.org/2005/11/COLLADASchema"}
_GREY = (0.7, 0.7, 0.7, 1.0)


@dataclass(frozen=True, eq=False)
class ColouredMesh:
    """``vertices`` (n, 3) [m] in the file's root frame, ``faces`` (m, 3) vertex indices, ``rgba`` the
    material's diffuse colour."""

    vertices: np.ndarray
    faces: np.ndarray
    rgba: tuple[float, float, float, float]


def _floats(text: str | None) -> np.ndarray:
    return np.array((text or "").split(), dtype=float)


def _id(url: str | None) -> str:
    return (url or "").lstrip("#")


def _colours(root: ET.Element) -> dict[str, tuple[float, ...]]:
    """material id -> diffuse rgba."""
    effects = {}
    for eff in root.iterfind(".//c:library_effects/c:effect", _NS):
        col = eff.find(".//c:diffuse/c:color", _NS)
        effects[eff.get("id")] = tuple(_floats(col.text)) if col is not None else _GREY
    out = {}
    for mat in root.iterfind(".//c:library_materials/c:material", _NS):
        inst = mat.find("c:instance_effect", _NS)
        out[mat.get("id")] = effects.get(_id(inst.get("url") if inst is not None else None), _GREY)
    return out


def _source(mesh: ET.Element, sid: str, where: str) -> np.ndarray:
    src = mesh.find(f"c:source[@id='{sid}']", _NS)
    if src is None:
        raise ModelError(f"no source {sid!r}", where=where)
    acc = src.find(".//c:accessor", _NS)
    stride = int(acc.get("stride", "3")) if acc is not None else 3
    return _floats(src.find("c:float_array", _NS).text).reshape(-1, stride)[:, :3]


def _primitives(geom: ET.Element, where: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(material symbol, positions (n, 3), faces (m, 3)) of each primitive of a geometry."""
    mesh = geom.find("c:mesh", _NS)
    if mesh is None:
        return []
    verts = {}
    for v in mesh.iterfind("c:vertices", _NS):
        pos = v.find("c:input[@semantic='POSITION']", _NS)
        verts[v.get("id")] = _source(mesh, _id(pos.get("source")), where)
    out = []
    for prim in mesh:
        tag = prim.tag.split("}")[-1]
        if tag not in ("triangles", "polylist"):
            continue
        inputs = prim.findall("c:input", _NS)
        stride = 1 + max(int(i.get("offset", "0")) for i in inputs)
        vin = next(i for i in inputs if i.get("semantic") == "VERTEX")
        idx = _floats(prim.find("c:p", _NS).text).astype(np.int64).reshape(-1, stride)
        idx = idx[:, int(vin.get("offset"))]
        if tag == "polylist":
            counts = _floats(prim.find("c:vcount", _NS).text).astype(np.int64)
            starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
            fans = [(s, s + k, s + k + 1)
                    for s, c in zip(starts, counts, strict=True) for k in range(1, c - 1)]
            faces = idx[np.array(fans, dtype=np.int64).reshape(-1, 3)]
        else:
            faces = idx.reshape(-1, 3)
        out.append((prim.get("material", ""), verts[_id(vin.get("source"))], faces))
    return out


def _node_matrix(node: ET.Element) -> np.ndarray:
    m = np.eye(4)
    for t in node:
        tag = t.tag.split("}")[-1]
        v = _floats(t.text)
        step = np.eye(4)
        if tag == "matrix":
            step = v.reshape(4, 4)
        elif tag == "translate":
            step[:3, 3] = v
        elif tag == "scale":
            step[:3, :3] = np.diag(v)
        elif tag == "rotate":
            axis, ang = v[:3] / np.linalg.norm(v[:3]), np.deg2rad(v[3])
            k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
            step[:3, :3] = np.eye(3) + np.sin(ang) * k + (1 - np.cos(ang)) * k @ k
        else:
            continue
        m = m @ step
    return m


def read_collada(path: str | Path) -> list[ColouredMesh]:
    """The visual scene of ``path`` as one :class:`ColouredMesh` per diffuse colour, vertices in metres in a
    z-up frame. ModelError for an unreadable file."""
    path = Path(path)
    where = str(path)
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as err:
        raise ModelError(f"cannot read COLLADA: {err}", where=where) from None
    unit = root.find("c:asset/c:unit", _NS)
    top = np.eye(4)
    top[:3, :3] *= float(unit.get("meter", "1")) if unit is not None else 1.0
    up = root.find("c:asset/c:up_axis", _NS)
    if up is not None and up.text == "Y_UP":  # y up -> z up: a quarter turn about x
        top = np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]]) @ top
    colours = _colours(root)
    geoms = {g.get("id"): g for g in root.iterfind(".//c:library_geometries/c:geometry", _NS)}
    groups: dict[tuple[float, ...], list[tuple[np.ndarray, np.ndarray]]] = {}

    def visit(node: ET.Element, parent: np.ndarray) -> None:
        m = parent @ _node_matrix(node)
        for inst in node.iterfind("c:instance_geometry", _NS):
            bind = {im.get("symbol"): _id(im.get("target"))
                    for im in inst.iterfind(".//c:instance_material", _NS)}
            for symbol, pos, faces in _primitives(geoms[_id(inst.get("url"))], where):
                world = pos @ m[:3, :3].T + m[:3, 3]
                rgba = tuple(float(x) for x in colours.get(bind.get(symbol, symbol), _GREY))
                groups.setdefault(rgba, []).append((world, faces))
        for child in node.iterfind("c:node", _NS):
            visit(child, m)

    for scene in root.iterfind(".//c:library_visual_scenes/c:visual_scene", _NS):
        for node in scene.iterfind("c:node", _NS):
            visit(node, top)
    out = []
    for rgba, parts in groups.items():
        offsets = np.cumsum([0] + [len(p) for p, _ in parts[:-1]])
        verts = np.concatenate([p for p, _ in parts])
        faces = np.concatenate([f + o for (_, f), o in zip(parts, offsets, strict=True)])
        out.append(ColouredMesh(verts, faces, rgba))  # type: ignore[arg-type]
    return out
