"""The two-mode study's table and figure from sweep folders (benchmarks.mode_study)."""

from __future__ import annotations

import pyarrow as pa
import pyarrow.parquet as pq

from benchmarks.mode_study import PAIRED_PANELS, format_mode_table, mode_rows, plot_mode_study


def _folder(path, shift: float):
    path.mkdir()
    results = []
    for subject in range(3):
        for mode, extra in (("hrc", 0.0), ("kwear-lookahead", shift)):
            results.append({"subject": subject, "seed": 0, "mode": mode, "status": "complete",
                            "kwear_integral": 100.0 + subject + extra, "repetition_time": 30.0 - extra / 10,
                            "takt_overruns": 1, "robot_share.a1": 0.5, "robot_share.a2": None})
    pq.write_table(pa.Table.from_pylist(results), path / "results.parquet")
    cells = [{"mode": "hrc", "kwear_integral.mean": 101.0},
             {"mode": "kwear-lookahead", "kwear_integral.mean": 101.0 + shift, "kwear_integral.diff": shift,
              "kwear_integral.diff_ci_low": shift - 1, "kwear_integral.diff_ci_high": shift + 1,
              "kwear_integral.wilcoxon_p": 0.25, "kwear_integral.pairs": 3}]
    keys = list(dict.fromkeys(k for c in cells for k in c))  # every column, None where a row has none
    pq.write_table(pa.Table.from_pylist([{k: c.get(k) for k in keys} for c in cells]), path / "cells.parquet")
    return path


def test_rows_table_and_figure(tmp_path):
    folders = {"a": _folder(tmp_path / "a", -5.0), "b": _folder(tmp_path / "b", 2.0)}
    base, other, rows = mode_rows(folders["a"], ["kwear_integral"])
    assert (base, other) == ("hrc", "kwear-lookahead")
    assert rows[0]["diff"] == -5.0 and rows[0]["p"] == 0.25 and rows[0]["pairs"] == 3
    table = format_mode_table({k: mode_rows(f, ["kwear_integral"]) for k, f in folders.items()})
    assert "| hrc | kwear-lookahead |" in table
    assert "| a | kwear_integral | 101 | 96 | -5 [-6, -4] | 0.25 (3) |" in table
    out = plot_mode_study(folders, tmp_path / "fig.png")
    assert out.stat().st_size > 10_000 and len(PAIRED_PANELS) == 3
