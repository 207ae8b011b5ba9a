"""A fingerprint of the code a unit runs: ergosim's source and the versions of the libraries whose numbers
shape a result.

A unit's id includes it (:func:`~ergosim.sweep.units.unit_id`), so finished units are reused only by the
same code: after an upgrade, or an edit of an editable install, a re-run over the same folder runs the
units again rather than mixing two versions of the twin in one table. A worker whose fingerprint differs
from the driver's (a cluster node with another install) fails its units and says so.
"""

from __future__ import annotations

import functools
import hashlib
from importlib import metadata
from pathlib import Path

import ergosim
from ergosim.blas_kernel import kernel

__all__ = ["code_fingerprint", "FINGERPRINT_DISTRIBUTIONS"]

FINGERPRINT_DISTRIBUTIONS = ("mujoco", "numpy", "scipy", "pin", "example-robot-data")
"""The libraries whose version enters the fingerprint: physics, numerics, kinematics, the robot models."""


@functools.cache
def code_fingerprint() -> str:
    """16 hex digits of the SHA-256 of every ``.py`` file of the ergosim package (path and bytes, in path
    order), the versions of :data:`FINGERPRINT_DISTRIBUTIONS` and the BLAS kernel numpy runs
    (:mod:`ergosim.blas_kernel`: two kernels round the worker's IK differently); computed once per
    process. The bundled scenarios, workcells and tasks enter a unit's id as the resolved scenario."""
    root = Path(ergosim.__file__).resolve().parent
    h = hashlib.sha256()
    for path in sorted(p for p in root.rglob("*.py") if "__pycache__" not in p.parts):
        h.update(path.relative_to(root).as_posix().encode("utf-8") + b"\0")
        h.update(path.read_bytes())
    h.update(f"blas=={kernel()}\0".encode())
    for dist in FINGERPRINT_DISTRIBUTIONS:
        try:
            version = metadata.version(dist)
        except metadata.PackageNotFoundError:
            version = "-"
        h.update(f"{dist}=={version}\0".encode())
    return h.hexdigest()[:16]
