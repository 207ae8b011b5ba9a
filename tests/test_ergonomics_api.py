"""Every name in the ergonomics package's and modules' __all__ exists; the issue's API is importable."""

from __future__ import annotations

import importlib

import pytest

import ergosim.ergonomics as pkg
from ergosim.ergonomics import part_scores
from ergosim.ergonomics.kwear import KWearParams, kwear_step, predict
from ergosim.ergonomics.rula import RulaResult, rula, table_a, table_b, table_c

MODULES = ["rula", "rula_parts", "rula_tables", "reba", "reba_parts", "reba_tables",
           "kwear", "calibration", "param_store", "risk_index", "cost", "features", "scores"]


def test_package_all_names_exist():
    assert len(pkg.__all__) == len(set(pkg.__all__))
    for name in pkg.__all__:
        assert getattr(pkg, name) is not None, name


@pytest.mark.parametrize("module", MODULES)
def test_module_all_names_exist(module):
    mod = importlib.import_module(f"ergosim.ergonomics.{module}")
    for name in mod.__all__:
        assert hasattr(mod, name), f"{module}.{name}"


def test_issue_api():
    assert all(callable(f) for f in (part_scores, kwear_step, predict, rula, table_a, table_b, table_c))
    fields = ("upper_arm", "lower_arm", "wrist", "wrist_twist", "neck", "trunk", "legs", "score_a", "score_b",
              "grand", "valid")
    assert set(fields) <= set(RulaResult._fields)
    p = KWearParams()
    assert (p.t_max, p.v_max, p.g_avg) == (240.0, 0.993, 3.0)
