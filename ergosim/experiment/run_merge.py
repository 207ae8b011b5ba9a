"""Merge shards of one run (``ergosim run --subject-range A:B``) into one run folder (``ergosim merge``).

Each shard keeps what its summary is computed from (``subject_records.json``). The merge checks that the
shards are finished runs of the same scenario, seed and protocol with disjoint subjects that join into
one contiguous range, then recomputes every statistic from the joined records through the same code a
run uses (:mod:`ergosim.experiment.summary`, :mod:`ergosim.experiment.outputs`): shards that cover every
subject give the unsharded ``summary.json``, ``allocations.csv``, ``failures.csv``, ``subjects.csv`` and
``subject_records.json`` byte for byte. Outputs the records cannot give are made from the shards' files
as their entry says: ``ticks.csv`` and ``kwear_actions.csv`` joined line by line in the run's order, the
KWear state files copied; the figures are drawn again from the merged files, as ``ergosim plot`` draws
them.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import os
from collections.abc import Sequence
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.experiment.outputs import Products, merge_outputs
from ergosim.experiment.run_folder import MANIFEST, RunFolder
from ergosim.experiment.subject_records import RECORDS_FILE, SubjectRecord, read_records
from ergosim.experiment.summary import summary_of

__all__ = ["Shard", "MergeResult", "read_shard", "merge_runs"]

log = logging.getLogger(__name__)

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
        for key in sorted(set(a) | set(b)):
            if a.get(key) != b.get(key):
                raise ConfigError(f"config {key} is {b.get(key)!r} here but {a.get(key)!r} in {first.path}: "
                                  "only shards of one run merge", where=str(s.path))


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
    log.debug("merging %d shard(s) of %s (seed %d), subjects %d..%d, into %s", len(shards), name, seed,
              subjects.start, subjects.stop - 1, out)
    folder = RunFolder(out, scenario=name, seed=seed)
    folder.claim(config)
    records = sorted((r for s in shards for r in s.records), key=lambda r: r.subject)
    span = (subjects.start, subjects.stop)
    try:
        summary = summary_of(name, seed, config, records, subject_range=span, complete=True,
                             status="complete")
        merge_outputs(out, Products(name, seed, config, tuple(records), span, summary),
                      [s.path for s in shards])
    except BaseException:
        folder.finish("failed", "the merge stopped before it wrote every file")
        raise
    status = summary["status"]
    folder.finish(status, f"{summary['repetitions_abandoned']} repetition(s) abandoned"
                  if status == "abandoned" else "")
    return MergeResult(summary, config, out, subjects)
