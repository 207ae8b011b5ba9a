"""Shards (issue 15): ``ergosim run --subject-range A:B`` and ``ergosim merge DIR...``; the merged summary is
the unsharded one byte for byte. Also the subject records a run folder keeps for that."""

from __future__ import annotations

import fnmatch
import json
import math
import shutil

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.experiment.outputs import OUTPUTS
from ergosim.experiment.run_folder import MANIFEST
from ergosim.experiment.subject_records import RunRecord, SubjectRecord, read_records, write_records
from ergosim.experiment.summary import summarise
from ergosim.twin.records import TICK_COLUMNS, Allocation, Failure, RepetitionOutcome, SubjectRun, TickLog

RUN = ["run", "multi-subject", "--subjects", "3", "--reps", "1", "--jobs", "1", "--quiet", "--set",
       "eta_max=2"]
SAME = ("summary.json", "subject_records.json", "allocations.csv", "failures.csv", "ticks.csv",
        "subjects.csv", "kwear_actions.csv", "allocation_histogram.png", "kwear_a1.png", "kwear_actions.png",
        "kwear_modes.png", "kwear_timeline_hrc.png", "kwear_state_s2_h-only.json", "decisions.csv",
        "cell.png", "report.html")


@pytest.fixture(scope="module")
def shards(tmp_path_factory):
    """The multi-subject protocol (hrc and h-only) for 3 subjects, whole and as shards 0:1 and 1:3."""
    tmp = tmp_path_factory.mktemp("shards")
    for name, extra in (("whole", []), ("a", ["--subject-range", "0:1"]), ("b", ["--subject-range", "1:"])):
        assert main([*RUN, *extra, "--out", str(tmp / name)]) == 0
    return tmp


@pytest.mark.slow
def test_a_shard_runs_only_its_subjects_seeded_as_in_the_whole_run(shards):
    whole = json.loads((shards / "whole" / "summary.json").read_text())
    b = json.loads((shards / "b" / "summary.json").read_text())
    assert b["subject_range"] == [1, 3] and b["subjects_planned"] == 2 and b["subjects"] == ["S02", "S03"]
    assert "subject_range" not in whole and whole["subjects_planned"] == 3
    for mode in ("hrc", "h-only"):
        key = "kwear_integral_by_subject"
        assert b["modes"][mode][key] == whole["modes"][mode][key][1:]
    assert b["complete"] is True and b["config"]["subjects"] == 3


@pytest.mark.slow
def test_merged_shards_are_the_unsharded_run_byte_for_byte(shards, tmp_path, capsys):
    out = tmp_path / "merged"
    assert main(["merge", str(shards / "b"), str(shards / "a"), "--out", str(out)]) == 0  # any order
    printed = capsys.readouterr().out
    assert "merged 2 run folder(s), subjects 0..2" in printed and "Wilcoxon" in printed
    for name in SAME:
        assert (out / name).read_bytes() == (shards / "whole" / name).read_bytes(), name
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in (shards / "whole").iterdir())
    assert json.loads((out / "run.json").read_text())["status"] == "complete"


def test_every_file_of_a_run_and_of_a_merge_is_one_entry_of_the_outputs_list(shards, tmp_path, capsys):
    """OUTPUTS is the one list of a run folder's files: each file matches one entry's names, and every entry
    but team.json (a team setting only) has its files in the run and in the merge."""
    out = tmp_path / "merged"
    assert main(["merge", str(shards / "a"), str(shards / "b"), "--out", str(out), "--quiet", "-v"]) == 0
    err = capsys.readouterr().err
    assert "DEBUG ergosim.experiment.run_merge: merging 2 shard(s) of multi-subject" in err
    for folder in (shards / "whole", out):
        names = [p.name for p in folder.iterdir() if p.name != MANIFEST]
        owners = {n: [o.name for o in OUTPUTS if any(fnmatch.fnmatch(n, f) for f in o.files)] for n in names}
        assert all(len(set(o)) == 1 for o in owners.values()), owners
        assert {o[0] for o in owners.values()} == {o.name for o in OUTPUTS} - {"team"}


@pytest.mark.slow
def test_merge_refuses_what_is_not_shards_of_one_run(shards, tmp_path, capsys):
    other = tmp_path / "other"
    # one subject is enough: the configs are compared before the subject ranges
    assert main([*RUN[:-2], "--set", "eta_max=3", "--subject-range", "2:3", "--out", str(other)]) == 0
    moved = tmp_path / "moved"  # issue 27: a task override changes no protocol field, and did merge
    assert main([*RUN, "--set", "task.agents.robot.cost=3", "--subject-range", "2:3",
                 "--out", str(moved)]) == 0
    assert json.loads((moved / "run.json").read_text())["config"]["overrides"] == {
        "eta_max": "2", "repetitions": "1", "subjects": "3", "task.agents.robot.cost": "3"}
    unfinished = tmp_path / "unfinished"
    shutil.copytree(shards / "b", unfinished)
    manifest = json.loads((unfinished / "run.json").read_text())
    (unfinished / "run.json").write_text(json.dumps({**manifest, "status": "interrupted"}))
    cases = [
        ([shards / "a", shards / "whole"], "subjects [0] are in both"),
        ([shards / "b", shards / "whole"], "are in both"),
        ([shards / "b"], None),  # a shard alone merges to itself (subjects 1..2)
        ([shards / "a", other], "run with --set eta_max=3 here but --set eta_max=2 in"),
        ([shards / "a", moved], "--set task.agents.robot.cost=3 here but no --set task.agents.robot"),
        ([shards / "a", unfinished], "the run is 'interrupted', not finished"),
        ([shards / "a", tmp_path / "nothing"], "not a directory"),
        ([shards / "a", tmp_path], "no subject_records.json"),
    ]
    capsys.readouterr()
    for k, (dirs, needle) in enumerate(cases):
        code = main(["merge", *map(str, dirs), "--out", str(tmp_path / f"m{k}"), "--quiet"])
        err = capsys.readouterr().err
        if needle is None:
            assert code == 0, err
            continue
        assert code == 2 and err.count("\n") == 1 and needle in err and "Traceback" not in err, err
        assert not (tmp_path / f"m{k}").exists()
    gap = tmp_path / "gap"
    assert main([*RUN, "--subject-range", "2:3", "--out", str(gap)]) == 0
    assert main(["merge", str(shards / "a"), str(gap), "--out", str(tmp_path / "g")]) == 2
    assert "no shard holds subjects 1..1" in capsys.readouterr().err
    assert main(["merge", str(shards / "a"), str(shards / "b"), "--out", str(shards / "a")]) == 2
    assert "is one of the shards" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["3:2", "a:b", "0:9", "5", "-1:2"])
def test_bad_subject_ranges_get_one_line_errors(capsys, tmp_path, value):
    code = main(["run", "multi-subject", "--subjects", "3", f"--subject-range={value}",
                 "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--subject-range" in err and "0 <= A < B <= 3" in err
    assert not (tmp_path / "o").exists()


def _run() -> SubjectRun:
    allocs = [Allocation(0, "hrc", 1, 0, "a1", "human", 0.1 + 1e-17, 2.5, 0.0, 1.0 / 3.0, had_choice=True),
              Allocation(0, "hrc", 1, 1, "a2", "robot", 0.7, 2.5, 1.0 / 3.0, 2.0, had_choice=False,
                         status="failed:unreachable", forced="robot"),
              Allocation(0, "hrc", 1, 2, "a2", "", math.nan, math.inf, 2.0, 2.0, had_choice=False,
                         status="pruned", allocatable=True)]
    ticks = TickLog(capacity=16)
    rng = np.random.default_rng(3)
    for _ in range(40):
        ticks.append(rng.random(len(TICK_COLUMNS)))
    failures = [Failure(2.0, 0, "hrc", 1, "a2", "robot", "failed:unreachable", "3 cm short")]
    outcomes = [RepetitionOutcome(0, "hrc", 1, "abandoned", "a2: every agent failed", 0.0, 2.0)]
    return SubjectRun(0, "hrc", allocs, ticks, 0, 1, 0.05, 0.8, failures=failures, outcomes=outcomes,
                      horizon=1.5)


def test_records_round_trip_exactly_and_summarise_as_the_run(tmp_path):
    run = _run()
    record = SubjectRecord(0, "S01", {"a1": 3}, {"a1": 1e-4}, {"a1": [0.9, 0.1 + 0.2]}, {"a1": 5.0},
                           {"hrc": RunRecord.of(run)})
    write_records(tmp_path / "r.json", scenario="x", seed=4, config={"modes": ["hrc"], "subjects": 1},
                  subject_range=(0, 1), records=[record])
    header, back = read_records(tmp_path / "r.json")
    assert header == {"scenario": "x", "seed": 4, "config": {"modes": ["hrc"], "subjects": 1},
                      "subject_range": [0, 1]}
    pruned = back[0].runs["hrc"].allocations[2]
    assert math.isnan(pruned.human_cost)
    assert pruned.robot_cost == math.inf
    assert back[0].runs["hrc"].allocations[:2] == record.runs["hrc"].allocations[:2]
    assert back[0].runs["hrc"].kwear_integral == run.kwear_integral and back[0].alphas == record.alphas
    actions = ["a1", "a2"]
    direct = json.dumps(summarise("x", 4, {"hrc": [run]}, actions=actions), sort_keys=True)
    again = json.dumps(summarise("x", 4, {"hrc": [back[0].runs["hrc"]]}, actions=actions), sort_keys=True)
    assert direct == again
