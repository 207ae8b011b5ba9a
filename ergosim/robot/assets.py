"""Locate robot descriptions shipped by the installed ``example-robot-data`` package.

The package has no Python module: its files live under ``site-packages/cmeel.prefix/share/example-robot-data``
and are found through the installed distribution's file list, so nothing is downloaded or copied at run
time. A URDF names its meshes by ``package://example-robot-data/...`` URLs; :func:`resolve_url` maps
them to files.
"""

from __future__ import annotations

import functools
import importlib.metadata
from pathlib import Path

from ergosim.errors import ModelError

__all__ = ["erd_share", "erd_file", "resolve_url"]

_PACKAGE = "example-robot-data"
_SHARE = "share/example-robot-data/"


@functools.cache
def erd_share() -> Path:
    """Absolute path of the installed ``.../share/example-robot-data`` directory."""
    try:
        files = importlib.metadata.files(_PACKAGE)
    except importlib.metadata.PackageNotFoundError:
        raise ModelError("the example-robot-data package is not installed; pip install example-robot-data",
                         where="ergosim.robot.assets") from None
    for f in files or ():
        s = str(f).replace("\\", "/")
        if _SHARE in s and s.endswith(".urdf"):
            path = Path(f.locate()).resolve()
            root = path.parents[len(Path(s.split(_SHARE, 1)[1]).parts) - 1]
            if root.is_dir():
                return root
    raise ModelError("example-robot-data is installed but ships no URDF under share/example-robot-data",
                     where="ergosim.robot.assets")


def erd_file(relative: str) -> Path:
    """``relative`` (e.g. ``robots/ur_description/urdf/ur5_gripper.urdf``) under :func:`erd_share`; ModelError
    if the installed package has no such file."""
    path = erd_share() / relative
    if not path.is_file():
        raise ModelError(f"example-robot-data has no {relative}", where="ergosim.robot.assets")
    return path


def resolve_url(url: str) -> Path:
    """The file a URDF's ``package://example-robot-data/<relative>`` URL names (a plain path passes)."""
    prefix = f"package://{_PACKAGE}/"
    return erd_file(url[len(prefix):]) if url.startswith(prefix) else Path(url)
