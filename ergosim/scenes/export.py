"""Save a workcell's compiled scene as a self-contained MJCF folder that plain MuJoCo opens.

``export_cell(spec, DIR)`` writes ``DIR/<cell name>.xml`` and every mesh it uses to ``DIR/assets/`` (the
robots' visual and collision meshes, STL parts), with ``meshdir="assets"``: the folder can be moved or
zipped and opened with ``mujoco.MjModel.from_xml_path`` or ``python -m mujoco.viewer --mjcf``. The MJCF is
MuJoCo's own save of the scene's MjSpec (``MjSpec.to_xml``): bodies, the human's mocap segments, the welds
(inactive) and the ``home`` keyframe. Nothing of the run (task, worker motion) is in it: it is the plant.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import NamedTuple

import mujoco

from ergosim.atomic import write_bytes, write_text
from ergosim.errors import ConfigError, ModelError
from ergosim.scenes.build import quiet_attach
from ergosim.scenes.cellbuild import cell_mjspec
from ergosim.scenes.cellspec import CellSpec

__all__ = ["ExportResult", "export_cell"]


class ExportResult(NamedTuple):
    """``path`` the MJCF written; ``assets`` the file names written to its ``assets/`` folder."""

    path: Path
    assets: tuple[str, ...]


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def _mesh_bytes(spec: mujoco.MjSpec, mesh) -> bytes:
    if mesh.file in spec.assets:
        return spec.assets[mesh.file]
    path = Path(mesh.file)
    try:
        return path.read_bytes()
    except OSError as err:
        raise ModelError(f"cannot read mesh {mesh.name!r} from {mesh.file}: {err.strerror or err}",
                         where="export") from None


def export_cell(spec: CellSpec, out: str | Path) -> ExportResult:
    """Write ``spec``'s scene to the folder ``out`` (created if needed): see the module docstring."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out} is a file; give a folder to write the scene into", where="--out")
    mspec = cell_mjspec(spec)
    blobs: dict[str, bytes] = {}
    for mesh in mspec.meshes:
        if not mesh.file:
            continue  # a mesh given by its vertices is written into the MJCF itself
        name = _safe(f"{mesh.name}{Path(mesh.file).suffix.lower()}")
        blobs[name] = _mesh_bytes(mspec, mesh)
        mesh.file = name
    mspec.meshdir = "assets"
    mspec.assets = {f"assets/{name}": blob for name, blob in blobs.items()}  # to_xml compiles first
    with quiet_attach():
        text = mspec.to_xml()
    try:
        for name, blob in blobs.items():
            write_bytes(out / "assets" / name, blob)
        path = out / f"{_safe(spec.name)}.xml"
        write_text(path, text)
    except OSError as err:
        raise ConfigError(f"cannot write the scene to {out}: {err.strerror or err}", where="--out") from None
    return ExportResult(path, tuple(sorted(blobs)))
