"""Load the Panda as a MuJoCo spec/model, with meshes resolved from the installed example-robot-data.

:func:`panda_spec` regenerates the MJCF from the URDF in memory (the committed ``models/panda/panda.xml``
is the same text, checked by a test), so scenes never depend on the repository checkout.
:func:`load_mjcf` loads any MJCF file of ``models/`` (e.g. ``models/panda/scene.xml``) and points its
``meshdir`` at the package.
"""

from __future__ import annotations

import functools
from pathlib import Path

import mujoco

from ergosim.errors import ModelError
from ergosim.robot.assets import panda_mesh_dir, panda_urdf
from ergosim.robot.mjcf import PandaGains, panda_xml
from ergosim.robot.urdf import read_urdf

__all__ = ["panda_mjcf_text", "panda_spec", "load_mjcf", "compile_spec"]


@functools.cache
def panda_mjcf_text(gains: PandaGains = PandaGains()) -> str:
    """The Panda MJCF generated from the installed URDF (what ``scripts/build_panda_mjcf.py`` writes)."""
    return panda_xml(read_urdf(panda_urdf()), gains)


def panda_spec(gains: PandaGains = PandaGains()) -> mujoco.MjSpec:
    """A fresh MjSpec of the Panda, base ``panda_link0`` at the world origin, meshdir set."""
    spec = mujoco.MjSpec.from_string(panda_mjcf_text(gains))
    spec.meshdir = str(panda_mesh_dir())
    return spec


def compile_spec(spec: mujoco.MjSpec, where: str = "MjSpec") -> mujoco.MjModel:
    """``spec.compile()`` with MuJoCo's error turned into a :class:`ModelError`."""
    try:
        return spec.compile()
    except ValueError as err:
        raise ModelError(f"MuJoCo cannot compile the model: {err}", where=where) from None


def load_mjcf(path: str | Path) -> mujoco.MjModel:
    """Compile an MJCF file; STL meshes it names are looked up in the installed Panda meshes."""
    path = Path(path)
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except ValueError as err:
        raise ModelError(f"cannot parse MJCF: {err}", where=str(path)) from None
    # files named in included MJCF come back prefixed with the including file's directory: keep the name
    mesh_dir = panda_mesh_dir()
    for mesh in spec.meshes:
        mesh.file = str(mesh_dir / Path(mesh.file).name)
    return compile_spec(spec, where=str(path))
