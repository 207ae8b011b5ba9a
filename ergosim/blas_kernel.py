"""One BLAS kernel on every x86-64 machine, so that the same seed gives the same bits on every machine.

numpy's bundled OpenBLAS chooses its kernels by the CPU when numpy is imported: the SkylakeX kernels on a
CPU with AVX-512, the Haswell kernels on one with AVX2. The two round the small matrix products of the
worker's whole-body IK differently in the last bit, and from the first solve that differs on, a run's
``ticks.csv`` does too (measured on an AVX-512 Xeon: ``ergosim run kwear-validation --reps 1`` differs from
line 141 of ``ticks.csv``; with the Haswell kernels it is the file an AVX2 machine writes, and
``tests/test_ik_golden.py`` passes on both). Every figure in the documentation was measured with the Haswell
kernels, so :func:`pin` asks OpenBLAS for them (``OPENBLAS_CORETYPE=Haswell``) wherever the CPU can run
them. numpy's own vector loops are not pinned: switching off their AVX-512 paths changed no byte of that run.

The pin works only before numpy is first imported, which ``import ergosim`` does first thing; a program that
imports numpy before ergosim keeps the kernel numpy chose (:func:`kernel` says which). Child processes
(``--jobs``, Ray workers, the video's renderers) inherit the setting. A user's own ``OPENBLAS_CORETYPE`` is
kept.
"""

from __future__ import annotations

import ctypes
import glob
import os
import platform
import sys

__all__ = ["PINNED", "pin", "kernel"]

PINNED = "Haswell"
"""The OpenBLAS kernel family every figure of this project was measured with (AVX2 and FMA)."""


def _cpu_flags() -> set[str]:
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as f:
            for line in f:
                if line.startswith("flags"):
                    return set(line.partition(":")[2].split())
    except OSError:
        pass
    return set()


def pin() -> bool:
    """Ask numpy's OpenBLAS for the :data:`PINNED` kernels; True if the setting is in place for the numpy
    this process will import. Nothing is set where numpy is already imported, where the user set
    ``OPENBLAS_CORETYPE``, or on a CPU without AVX2 and FMA (the kernels would not run there)."""
    if "OPENBLAS_CORETYPE" in os.environ:
        return os.environ["OPENBLAS_CORETYPE"] == PINNED and "numpy" not in sys.modules
    if "numpy" in sys.modules or platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    if not {"avx2", "fma"} <= _cpu_flags():
        return False
    os.environ["OPENBLAS_CORETYPE"] = PINNED
    return True


def kernel() -> str | None:
    """The kernel family numpy's bundled OpenBLAS runs in this process (e.g. ``"Haswell"``), or None where
    numpy links another BLAS or the name cannot be read."""
    import numpy  # noqa: PLC0415

    libs = os.path.join(os.path.dirname(os.path.dirname(numpy.__file__)), "numpy.libs")
    for path in glob.glob(os.path.join(libs, "libscipy_openblas*.so")):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for symbol in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename",
                       "openblas_get_corename"):
            fn = getattr(lib, symbol, None)
            if fn is not None:
                fn.restype = ctypes.c_char_p
                return fn().decode("ascii", "replace").strip() or None
    return None
