"""Locate the Panda description shipped by the installed ``example-robot-data`` package.

The package has no Python module: its files live under ``site-packages/cmeel.prefix/share/example-robot-data``
and are found through the installed distribution's file list, so nothing is downloaded or copied.
"""

from __future__ import annotations

import functools
import importlib.metadata
from pathlib import Path

from ergosim.errors import ModelError

__all__ = ["PANDA_SUBDIR", "panda_description_dir", "panda_urdf", "panda_mesh_dir", "panda_license"]

PANDA_SUBDIR = "robots/panda_description"


@functools.cache
def _erd_share() -> Path:
    try:
        files = importlib.metadata.files("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise ModelError("the example-robot-data package is not installed; pip install example-robot-data",
                         where="ergosim.robot.assets") from None
    for f in files or ():
        s = str(f).replace("\\", "/")
        if s.endswith(f"{PANDA_SUBDIR}/urdf/panda.urdf"):
            root = Path(f.locate()).resolve().parents[3]
            if root.is_dir():
                return root
    raise ModelError("example-robot-data is installed but ships no robots/panda_description/urdf/panda.urdf",
                     where="ergosim.robot.assets")


def panda_description_dir() -> Path:
    """Absolute path of ``.../share/example-robot-data/robots/panda_description``."""
    return _erd_share() / PANDA_SUBDIR


def panda_urdf() -> Path:
    """The Panda URDF (7 arm joints, hand, two prismatic fingers, ``panda_hand_tcp`` frame)."""
    return panda_description_dir() / "urdf" / "panda.urdf"


def panda_mesh_dir() -> Path:
    """Directory of the collision STL meshes (also used, coloured, as visual meshes: MuJoCo reads no .dae)."""
    return panda_description_dir() / "meshes" / "collision"


def panda_license() -> Path:
    return panda_description_dir() / "LICENSE"
