"""The BLAS kernel pin (ergosim/blas_kernel.py): ``import ergosim`` before numpy runs numpy's OpenBLAS on the
Haswell kernels wherever the CPU has AVX2 and FMA, so a seed gives the same bits on AVX2 and AVX-512
machines; a user's own OPENBLAS_CORETYPE and a numpy imported first are left alone."""

from __future__ import annotations

import os
import platform
import subprocess
import sys

from ergosim.blas_kernel import PINNED, _cpu_flags

PROBE = ("import os, sys; {first}import ergosim; from ergosim.blas_kernel import kernel; "
         "print(os.environ.get('OPENBLAS_CORETYPE'), kernel())")


def _probe(first: str = "", **env: str) -> list[str]:
    clean = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    out = subprocess.run([sys.executable, "-c", PROBE.format(first=first)], env={**clean, **env},
                         capture_output=True, text=True, check=True).stdout.split()
    return out


def _can_pin() -> bool:
    return platform.machine().lower() in ("x86_64", "amd64") and {"avx2", "fma"} <= _cpu_flags()


def test_importing_ergosim_first_pins_the_haswell_kernels_where_the_cpu_runs_them():
    setting, kernel = _probe()
    if _can_pin():
        assert (setting, kernel.lower()) == (PINNED, PINNED.lower())
    else:
        assert setting == "None"


def test_a_users_own_kernel_setting_is_kept():
    setting, _ = _probe(OPENBLAS_CORETYPE="Sandybridge")
    assert setting == "Sandybridge"


def test_a_numpy_imported_first_is_left_alone():
    setting, _ = _probe(first="import numpy; ")
    assert setting == "None"


def test_this_test_process_runs_the_pinned_kernels():
    """The suite itself (conftest imports ergosim before numpy): the golden IK bits are checked on the
    kernels they were made with."""
    from ergosim.blas_kernel import kernel  # noqa: PLC0415

    if _can_pin():
        assert (kernel() or "").lower() == PINNED.lower()
