"""Merge shards of one run (``ergosim run --subject-range A:B``) into one run folder (``ergosim merge``).

Each shard keeps what its summary is computed from (``subject_records.json``). The merge checks that the
shards are finished runs of the same scenario, seed and protocol with disjoint subjects that join into
one contiguous range, then recomputes every statistic from the joined records through the same code a
run uses (:mod:`ergosim.twin.run_summary`): shards that cover every subject give the unsharded
``summary.json``, ``allocations.csv``, ``failures.csv``, ``subjects.csv`` and ``subject_records.json``
byte for byte. ``ticks.csv`` and ``kwear_actions.csv`` are joined line by line in the run's order, the
KWear state files are copied, and the figures are drawn again from the merged files, as
``ergosim plot`` draws them.
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Sequence
from pathlib import Path

from ergosim.atomic import atomic_open, write_bytes
from ergosim.errors import ConfigError
from ergosim.twin.plots import write_plots
from ergosim.twin.report import write_subjects, write_summary
from ergosim.twin.run_folder import MANIFEST, RunFolder
from ergosim.twin.run_summary import summary_of, write_record_files
from ergosim.twin.subject_records import RECORDS_FILE, SubjectRecord, read_records

__all__ = ["Shard", "MergeResult", "read_shard", "merge_runs"]

_MERGEABLE = ("complete", "abandoned")


@dataclasses.dataclass(frozen=True)
class Shard:
    """One run folder to merge: its header (scenario, seed, config, subject_range) and records."""

    path: Path
    header: dict
    records: tuple[SubjectRecord, ...]

    @property
    def subjects(self) -> range:
        return range(*self.header["subject_range"])


@dataclasses.dataclass(frozen=True)
class MergeResult:
    summary: dict
    config: dict
    out: Path
    subjects: range


def read_shard(path: str | os.PathLike[str]) -> Shard:
    """A finished run folder's records; a missing, unfinished or partial shard is a ConfigError."""
    path = Path(path)
    if not path.is_dir():
        raise ConfigError("not a directory", where=str(path))
    header, records = read_records(path / RECORDS_FILE)
    status = _status(path)
    if status not in _MERGEABLE:
        raise ConfigError(f"the run is {status!r}, not finished; run its subjects again before merging",
                          where=str(path))
    wanted = range(*header["subject_range"])
    have = sorted(r.subject for r in records)
    if have != list(wanted):
        missing = sorted(set(wanted) - set(have))
        raise ConfigError(f"holds subjects {have} of its range {wanted.start}:{wanted.stop}; missing "
                          f"{missing}", where=str(path))
    return Shard(path, header, tuple(records))


def _status(path: Path) -> str:
    try:
        return str(json.loads((path / MANIFEST).read_text(encoding="utf-8")).get("status"))
    except (OSError, ValueError, AttributeError):
        return "unknown (no readable run.json)"


def _check_same(shards: Sequence[Shard]) -> None:
    first = shards[0]
    for s in shards[1:]:
        for key in ("scenario", "seed"):
            if s.header[key] != first.header[key]:
                raise ConfigError(f"{key} is {s.header[key]!r} here but {first.header[key]!r} in "
                                  f"{first.path}: only shards of one run merge", where=str(s.path))
        a, b = first.header["config"], s.header["config"]
        ours, theirs = a.get("overrides") or {}, b.get("overrides") or {}
        for key in sorted(set(ours) | set(theirs)):
            if ours.get(key) != theirs.get(key):
                raise ConfigError(f"run with {_said(key, theirs)} here but {_said(key, ours)} in "
                                  f"{first.path}: only shards of one run merge", where=str(s.path))
        for key in sorted(set(a) | set(b)):
            if a.get(key) != b.get(key):
                raise ConfigError(f"config {key} is {b.get(key)!r} here but {a.get(key)!r} in {first.path}: "
                                  "only shards of one run merge", where=str(s.path))


def _said(key: str, overrides: dict) -> str:
    return f"--set {key}={overrides[key]}" if key in overrides else f"no --set {key}"


def _joined_range(shards: Sequence[Shard]) -> range:
    ordered = sorted(shards, key=lambda s: s.subjects.start)
    for prev, nxt in zip(ordered, ordered[1:], strict=False):
        if nxt.subjects.start < prev.subjects.stop:
            both = sorted(set(prev.subjects) & set(nxt.subjects))
            raise ConfigError(f"subjects {both} are in both {prev.path} and {nxt.path}", where=str(nxt.path))
        if nxt.subjects.start > prev.subjects.stop:
            raise ConfigError(f"no shard holds subjects {prev.subjects.stop}..{nxt.subjects.start - 1} "
                              f"(between {prev.path} and {nxt.path})", where="ergosim merge")
    return range(ordered[0].subjects.start, ordered[-1].subjects.stop)


def _header(paths: Sequence[Path], name: str) -> str:
    headers = []
    for p in paths:
        with p.open(encoding="utf-8") as f:
            headers.append(f.readline())
    if len(set(headers)) != 1:
        raise ConfigError(f"{name} columns differ between shards", where=str(paths[0].parent))
    return headers[0]


def _merge_lines(shards: Sequence[Shard], name: str, out: Path, groups: Sequence[str] | None = None) -> None:
    """``name`` of the run from the shards' (in subject order): every shard's lines, or with ``groups``
    (modes) the lines of each group (the second column) in turn, as ticks.csv orders mode, then subject."""
    paths = [s.path / name for s in shards]
    if not all(p.is_file() for p in paths):
        return
    header = _header(paths, name)
    with atomic_open(out / name, "w") as dst:
        dst.write(header)
        for group in groups if groups is not None else [None]:
            for p in paths:
                with p.open(encoding="utf-8", newline="") as f:
                    next(f)
                    for line in f:
                        if group is None or line.split(",", 2)[1] == group:
                            dst.write(line)


def merge_runs(dirs: Sequence[str | os.PathLike[str]], out: str | os.PathLike[str]) -> MergeResult:
    """Merge the run folders ``dirs`` (shards of one run) into ``out``, which the merge owns (run.json)."""
    if not dirs:
        raise ConfigError("give the run folders to merge", where="ergosim merge")
    out = Path(out)
    shards = sorted((read_shard(d) for d in dirs), key=lambda s: s.subjects.start)
    for s in shards:
        if out.exists() and s.path.resolve() == out.resolve():
            raise ConfigError(f"{out} is one of the shards; merge into another folder", where="--out")
    _check_same(shards)
    subjects = _joined_range(shards)
    header = shards[0].header
    config, name, seed = header["config"], header["scenario"], header["seed"]
    if "execution" in config:  # the record of a protocol whose team settings are not the paper's
        raise ConfigError(f"{shards[0].path} is a team-execution run (execution = {config['execution']!r}); "
                          "its team.json is computed from the per-tick logs and cannot be merged from shards",
                          where="ergosim merge")
    folder = RunFolder(out, scenario=name, seed=seed)
    folder.claim(config)
    records = sorted((r for s in shards for r in s.records), key=lambda r: r.subject)
    span = (subjects.start, subjects.stop)
    try:
        summary = summary_of(name, seed, config, records, subject_range=span, complete=True,
                             status="complete")
        write_record_files(out, name, seed, config, records, subject_range=span)
        _merge_lines(shards, "ticks.csv", out, groups=sorted(config["modes"]))
        _merge_lines(shards, "kwear_actions.csv", out)
        write_subjects(out / "subjects.csv", [(r.name, r.runs[m]) for m in config["modes"] for r in records
                                              if m in r.runs])
        for s in shards:
            for state in sorted(s.path.glob("kwear_state_s*_*.json")):
                write_bytes(out / state.name, state.read_bytes())
        if (out / "ticks.csv").is_file():
            write_plots(out)
        write_summary(out / "summary.json", summary)
    except BaseException:
        folder.finish("failed", "the merge stopped before it wrote every file")
        raise
    status = summary["status"]
    folder.finish(status, f"{summary['repetitions_abandoned']} repetition(s) abandoned"
                  if status == "abandoned" else "")
    return MergeResult(summary, config, out, subjects)
