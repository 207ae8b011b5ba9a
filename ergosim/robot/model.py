"""A robot's MuJoCo model: generated from its URDF, committed under ``models/<name>/``, loaded as an MjSpec.

:func:`robot_files` builds the MJCF text and its assets from the installed example-robot-data (what
``scripts/build_robot_mjcf.py`` writes to ``models/<name>/``; a test checks the committed files equal it).
:func:`robot_spec` loads the committed folder when the source tree has it and otherwise builds the same
files in memory, so a scene never needs the checkout; mesh files are named by absolute path (or held in
the spec's in-memory assets), so the spec can be attached to any scene.
"""

from __future__ import annotations

import functools
from pathlib import Path

import mujoco

from ergosim.atomic import write_bytes, write_text
from ergosim.errors import ModelError
from ergosim.robot.assets import erd_file
from ergosim.robot.mjcf import RobotFiles, robot_mjcf
from ergosim.robot.robot_model import RobotModel, get_robot
from ergosim.robot.urdf import read_urdf

__all__ = ["MODELS_DIR", "model_dir", "robot_files", "robot_spec", "scene_xml", "write_model", "compile_spec",
           "load_mjcf"]

MODELS_DIR = Path(__file__).resolve().parents[2] / "models"
"""``models/`` of the source tree (mujoco_menagerie layout)."""


def model_dir(robot: RobotModel) -> Path:
    """``models/<name>/`` of ``robot``."""
    return MODELS_DIR / robot.name


@functools.cache
def _files(name: str) -> RobotFiles:
    robot = get_robot(name)
    urdf = read_urdf(erd_file(robot.urdf))
    if robot.edit_urdf is not None:
        urdf = robot.edit_urdf(urdf)
    return robot_mjcf(urdf, robot.recipe)


def robot_files(robot: RobotModel) -> RobotFiles:
    """The MJCF text and asset files of ``robot``, built from the installed URDF (cached per process)."""
    return _files(robot.name)


def robot_spec(robot: RobotModel) -> mujoco.MjSpec:
    """A fresh MjSpec of ``robot``, base at the world origin, its meshes resolvable from any scene."""
    path = model_dir(robot) / f"{robot.name}.xml"
    if path.is_file():
        spec = _parse(path)
        return spec
    files = robot_files(robot)
    assets = {f"{robot.name}/{k}": v for k, v in files.assets.items()}
    spec = mujoco.MjSpec.from_string(files.xml.replace('meshdir="assets"', f'meshdir="{robot.name}"'),
                                     assets=assets)
    spec.assets = assets  # attach() does not carry a child's assets; the scene copies them from here
    return spec


_SCENE = """<mujoco model="{name} scene">
  <include file="{name}.xml"/>

  <statistic center="0.3 0 0.4" extent="1"/>

  <visual>
    <headlight diffuse="0.6 0.6 0.6" ambient="0.3 0.3 0.3" specular="0 0 0"/>
    <global azimuth="120" elevation="-20"/>
  </visual>

  <asset>
    <texture type="skybox" builtin="gradient" rgb1="0.3 0.5 0.7" rgb2="0 0 0" width="512" height="3072"/>
    <texture type="2d" name="groundplane" builtin="checker" mark="edge" rgb1="0.2 0.3 0.4" rgb2="0.1 0.2 0.3"
      markrgb="0.8 0.8 0.8" width="300" height="300"/>
    <material name="groundplane" texture="groundplane" texuniform="true" texrepeat="5 5" reflectance="0.2"/>
  </asset>

  <worldbody>
    <light pos="0 0 1.5" dir="0 0 -1" directional="true"/>
    <geom name="floor" size="0 0 0.05" type="plane" material="groundplane"/>
  </worldbody>
</mujoco>
"""


def scene_xml(name: str) -> str:
    """``models/<name>/scene.xml``: the robot on a floor, with a light and a sky (menagerie's scene)."""
    return _SCENE.format(name=name)


def write_model(name: str, directory: Path | None = None) -> Path:
    """Write robot ``name``'s MJCF, its ``scene.xml`` and its assets to ``directory`` (default
    ``models/<name>/``), removing asset files the model no longer names; returns the MJCF path."""
    robot = get_robot(name)
    directory = model_dir(robot) if directory is None else Path(directory)
    files = robot_files(robot)
    assets = directory / "assets"
    for blob_name, blob in files.assets.items():
        write_bytes(assets / blob_name, blob)
    for stale in assets.iterdir():
        if stale.name not in files.assets:
            stale.unlink()
    path = directory / f"{name}.xml"
    write_text(path, files.xml)
    write_text(directory / "scene.xml", scene_xml(name))
    return path


def compile_spec(spec: mujoco.MjSpec, where: str = "MjSpec") -> mujoco.MjModel:
    """``spec.compile()`` with MuJoCo's error turned into a :class:`ModelError`."""
    try:
        return spec.compile()
    except ValueError as err:
        raise ModelError(f"MuJoCo cannot compile the model: {err}", where=where) from None


def _parse(path: Path) -> mujoco.MjSpec:
    """Parse an MJCF file and name each mesh by its absolute path (an attached spec loses its meshdir)."""
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except ValueError as err:
        raise ModelError(f"cannot parse MJCF: {err}", where=str(path)) from None
    for mesh in spec.meshes:
        if mesh.file:
            mesh.file = str((path.parent / spec.meshdir / mesh.file).resolve())
    spec.meshdir = ""
    return spec


def load_mjcf(path: str | Path) -> mujoco.MjModel:
    """Compile an MJCF file of ``models/`` (e.g. ``models/<robot>/scene.xml``), as plain MuJoCo would."""
    path = Path(path)
    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except ValueError as err:
        raise ModelError(f"MuJoCo cannot load the model: {err}", where=str(path)) from None
