"""A small reader for the parts of a URDF the MJCF builder needs: links (inertia, mesh) and joints.

Only what example-robot-data's robots use is read (revolute, prismatic and fixed joints; mesh and box
geometry). Anything malformed is a :class:`~ergosim.errors.ModelError` naming the element.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ergosim.errors import ModelError
from ergosim.quat import from_rpy

__all__ = ["Origin", "Inertial", "Shape", "Link", "Joint", "Urdf", "read_urdf"]


@dataclass(frozen=True)
class Origin:
    """A pose in the parent frame: ``xyz`` [m], ``rpy`` [rad]."""

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def quat(self) -> np.ndarray:
        """(4,) wxyz of ``rpy``."""
        return from_rpy(self.rpy)

    @property
    def is_identity_rotation(self) -> bool:
        return all(abs(a) < 1e-12 for a in self.rpy)


@dataclass(frozen=True)
class Inertial:
    """Mass [kg], centre of mass (``origin``) and inertia about it (ixx iyy izz ixy ixz iyz) [kg m^2]."""

    origin: Origin
    mass: float
    inertia: tuple[float, float, float, float, float, float]


@dataclass(frozen=True)
class Shape:
    """A visual or collision geometry: ``kind`` "mesh" (``mesh`` = file stem, ``file`` the URDF's filename,
    e.g. a ``package://`` URL) or "box" (``size`` full [m])."""

    kind: str
    origin: Origin
    mesh: str = ""
    size: tuple[float, float, float] = (0.0, 0.0, 0.0)
    file: str = ""


@dataclass(frozen=True)
class Link:
    name: str
    inertial: Inertial | None
    visuals: tuple[Shape, ...] = ()
    collisions: tuple[Shape, ...] = ()


@dataclass(frozen=True)
class Joint:
    """``kind`` revolute | prismatic | fixed; ``lower``/``upper`` [rad or m], ``effort`` [N m or N],
    ``velocity`` [rad/s or m/s] from ``<limit>``; ``mimic`` the joint this one copies, if any."""

    name: str
    kind: str
    parent: str
    child: str
    origin: Origin
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    lower: float = 0.0
    upper: float = 0.0
    effort: float = 0.0
    velocity: float = 0.0
    damping: float = 0.0
    mimic: str = ""


@dataclass(frozen=True)
class Urdf:
    name: str
    links: dict[str, Link] = field(default_factory=dict)
    joints: tuple[Joint, ...] = ()

    def children(self, link: str) -> list[Joint]:
        return [j for j in self.joints if j.parent == link]

    def root(self) -> str:
        childs = {j.child for j in self.joints}
        roots = [n for n in self.links if n not in childs]
        if len(roots) != 1:
            raise ModelError(f"expected one root link, found {roots}", where=self.name)
        return roots[0]

    def joint(self, name: str) -> Joint:
        for j in self.joints:
            if j.name == name:
                return j
        raise ModelError(f"no joint {name!r}", where=self.name)


def _floats(text: str | None, n: int, where: str) -> tuple[float, ...]:
    try:
        vals = tuple(float(v) for v in (text or "").split())
    except ValueError:
        raise ModelError(f"expected {n} numbers, got {text!r}", where=where) from None
    if len(vals) != n:
        raise ModelError(f"expected {n} numbers, got {text!r}", where=where)
    return vals


def _origin(el: ET.Element | None, where: str) -> Origin:
    if el is None:
        return Origin()
    return Origin(_floats(el.get("xyz", "0 0 0"), 3, where), _floats(el.get("rpy", "0 0 0"), 3, where))


def _shape(el: ET.Element, where: str) -> Shape | None:
    geo = el.find("geometry")
    if geo is None:
        raise ModelError("a visual/collision without <geometry>", where=where)
    origin = _origin(el.find("origin"), where)
    mesh, box = geo.find("mesh"), geo.find("box")
    if mesh is not None:
        filename = mesh.get("filename", "")
        return Shape("mesh", origin, mesh=Path(filename).stem, file=filename)
    if box is not None:
        return Shape("box", origin, size=_floats(box.get("size"), 3, where))
    return None


def read_urdf(path: str | Path) -> Urdf:
    """Parse ``path`` into an :class:`Urdf` (links in file order, joints in file order)."""
    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as err:
        raise ModelError(f"cannot read URDF: {err}", where=str(path)) from None
    links: dict[str, Link] = {}
    for el in root.findall("link"):
        name = el.get("name", "")
        where = f"{path.name}: link {name}"
        inertial = None
        iel = el.find("inertial")
        if iel is not None:
            mass = float(iel.find("mass").get("value"))  # type: ignore[union-attr]
            ie = iel.find("inertia")
            inertia = tuple(float(ie.get(k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))  # type: ignore
            inertial = Inertial(_origin(iel.find("origin"), where), mass, inertia)  # type: ignore[arg-type]
        visuals = tuple(s for s in (_shape(v, where) for v in el.findall("visual")) if s)
        collisions = tuple(s for s in (_shape(c, where) for c in el.findall("collision")) if s)
        links[name] = Link(name, inertial, visuals, collisions)
    joints = []
    for el in root.findall("joint"):
        name = el.get("name", "")
        where = f"{path.name}: joint {name}"
        lim, dyn, mim = el.find("limit"), el.find("dynamics"), el.find("mimic")
        joints.append(Joint(
            name=name,
            kind=el.get("type", ""),
            parent=el.find("parent").get("link"),  # type: ignore[union-attr]
            child=el.find("child").get("link"),  # type: ignore[union-attr]
            origin=_origin(el.find("origin"), where),
            axis=_floats(el.find("axis").get("xyz"), 3, where) if el.find("axis") is not None else (1, 0, 0),
            lower=float(lim.get("lower", 0)) if lim is not None else 0.0,
            upper=float(lim.get("upper", 0)) if lim is not None else 0.0,
            effort=float(lim.get("effort", 0)) if lim is not None else 0.0,
            velocity=float(lim.get("velocity", 0)) if lim is not None else 0.0,
            damping=float(dyn.get("damping", 0)) if dyn is not None else 0.0,
            mimic=mim.get("joint", "") if mim is not None else "",
        ))
    return Urdf(root.get("name", path.stem), links, tuple(joints))
