"""``Results.frames()``: a run's allocations, ticks and subjects as pandas DataFrames (the ``analysis``
extra), equal to the CSV files the run wrote; DuckDB queries them; without pandas, one line names the
extra."""

from __future__ import annotations

import builtins
import csv
import dataclasses

import duckdb
import numpy as np
import pandas as pd
import pytest

from ergosim import api
from ergosim.errors import ConfigError
from ergosim.experiment.csv_files import SUBJECT_COLUMNS
from ergosim.twin.records import TICK_COLUMNS, Allocation


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    out = tmp_path_factory.mktemp("frames") / "out"
    sc = api.load("kwear-validation", {"eta_max": "2"}, subjects=2, repetitions=1, modes=["hrc", "rula"])
    return api.run(sc, seed=0, out=out), out


def test_the_frames_hold_every_record_of_the_run(done):
    res, out = done
    f = res.frames()
    assert isinstance(f.allocations, pd.DataFrame) and isinstance(f.ticks, pd.DataFrame)
    assert list(f.allocations.columns) == [x.name for x in dataclasses.fields(Allocation)]
    assert len(f.allocations) == len(res.allocations)
    assert f.allocations.to_dict("records") == [dataclasses.asdict(a) for a in res.allocations]
    assert list(f.ticks.columns) == ["subject", "mode", *TICK_COLUMNS]
    assert len(f.ticks) == sum(len(r.ticks.rows) for s in res.subjects for r in s.runs.values())
    assert f.ticks["repetition"].dtype.kind == "i" and set(f.ticks["mode"]) == {"hrc", "rula"}
    assert list(f.subjects.columns) == list(SUBJECT_COLUMNS) and len(f.subjects) == 4


def test_the_frames_equal_the_files_of_the_run(done):
    res, out = done
    f = res.frames()
    subjects = pd.read_csv(out / "subjects.csv")  # floats written exactly (repr)
    key = ["subject", "mode"]
    pd.testing.assert_frame_equal(f.subjects.sort_values(key).reset_index(drop=True),
                                  subjects.sort_values(key).reset_index(drop=True), check_dtype=False)
    ticks = pd.read_csv(out / "ticks.csv")  # 9 significant digits
    mine = f.ticks.sort_values(key, kind="stable").reset_index(drop=True)
    theirs = ticks.sort_values(key, kind="stable").reset_index(drop=True)
    assert list(mine.columns) == list(theirs.columns)
    np.testing.assert_allclose(mine["kwear_neck"], theirs["kwear_neck"], rtol=1e-8)
    with (out / "allocations.csv").open(encoding="utf-8", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["action"], r["agent"], r["status"]) for r in rows] == \
        list(f.allocations[["action", "agent", "status"]].itertuples(index=False, name=None))


def test_duckdb_queries_the_frames(done):
    allocations = done[0].frames().allocations  # noqa: F841 - DuckDB reads the local DataFrame by name
    got = duckdb.sql("select mode, count(*) as n from allocations where status = 'done' group by mode "
                     "order by mode").fetchall()
    assert got == [("hrc", 5 * 2), ("rula", 5 * 2)]


def test_without_pandas_one_line_names_the_extra(done, monkeypatch):
    real = builtins.__import__

    def no_pandas(name, *args, **kw):
        if name == "pandas" or name.startswith("pandas."):
            raise ImportError("No module named 'pandas'")
        return real(name, *args, **kw)

    monkeypatch.setattr(builtins, "__import__", no_pandas)
    with pytest.raises(ConfigError) as err:
        done[0].frames()
    assert str(err.value) == ("frames: pandas is not installed: pip install 'ergosim[analysis]' "
                              "(pandas and duckdb)")
