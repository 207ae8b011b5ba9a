"""Rows waiting to be sent, per entity, so that history goes out in a few large ``send_columns`` calls.

A ``send_columns`` call costs about the same (~0.25 ms) for 1 row as for 1000, so the recorder buffers
ticks and decisions and sends each entity's rows in one call per flush, whatever the batch size the loop
uses. Every row carries both timelines: ``sim_time`` [s] and ``repetition``.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import rerun as rr

from ergosim.viz.paths import REPETITION, SIM_TIME

__all__ = ["ColumnBuffer"]


class ColumnBuffer:
    """Per-entity rows of one archetype each: Scalars, Transform3D (translation + xyzw quaternion) or
    TextLog. Rows of an entity are sent in the order they were added."""

    def __init__(self) -> None:
        self._scalars: dict[str, list[tuple[np.ndarray, ...]]] = defaultdict(list)
        self._poses: dict[str, list[tuple[np.ndarray, ...]]] = defaultdict(list)
        self._texts: dict[str, list[tuple[float, int, str, tuple[int, int, int]]]] = defaultdict(list)

    def __bool__(self) -> bool:
        return bool(self._scalars or self._poses or self._texts)

    def scalars(self, entity: str, t: np.ndarray, rep: np.ndarray, values: np.ndarray) -> None:
        """(n,) times [s], (n,) repetitions, (n,) values; nothing is kept for n = 0."""
        if len(t):
            self._scalars[entity].append((t, rep, values))

    def poses(self, entity: str, t: np.ndarray, rep: np.ndarray, translation: np.ndarray,
              quat_xyzw: np.ndarray) -> None:
        """(n,) times [s], (n,) repetitions, (n, 3) translations [m], (n, 4) xyzw quaternions."""
        if len(t):
            self._poses[entity].append((t, rep, translation, quat_xyzw))

    def text(self, entity: str, t: float, rep: int, text: str, color: tuple[int, int, int],
             level: str = "INFO") -> None:
        self._texts[entity].append((t, rep, text, color, level))

    def send(self, stream: rr.RecordingStream) -> None:
        """Send everything buffered, one call per entity, and empty the buffer."""
        indexes = _SharedIndexes()
        for entity, rows in self._poses.items():
            trans, quat = (np.concatenate(c) for c in tuple(zip(*rows, strict=True))[2:])
            stream.send_columns(entity, indexes=indexes(rows),
                                columns=rr.Transform3D.columns(translation=trans, quaternion=quat))
        for entity, rows in self._scalars.items():
            values = np.concatenate([r[2] for r in rows])
            stream.send_columns(entity, indexes=indexes(rows), columns=rr.Scalars.columns(scalars=values))
        for entity, rows in self._texts.items():
            t, rep, text, color, level = zip(*rows, strict=True)
            stream.send_columns(entity, indexes=_indexes(np.array(t), np.array(rep)),
                                columns=rr.TextLog.columns(text=list(text), level=list(level),
                                                           color=np.array(color, dtype=np.uint8)))
        self._scalars.clear()
        self._poses.clear()
        self._texts.clear()


class _SharedIndexes:
    """Time columns built once per distinct list of (t, rep) arrays: entities with no dropout in a batch
    were given the very same arrays, so most entities share one pair of columns."""

    def __init__(self) -> None:
        self._cache: dict[tuple[int, ...], tuple[list[rr.TimeColumn], list]] = {}

    def __call__(self, rows: list[tuple[np.ndarray, ...]]) -> list[rr.TimeColumn]:
        key = tuple(id(a) for r in rows for a in r[:2])
        if key not in self._cache:  # the rows are kept in the entry so their ids stay unique
            t = np.concatenate([r[0] for r in rows])
            rep = np.concatenate([r[1] for r in rows])
            self._cache[key] = (_indexes(t, rep), rows)
        return self._cache[key][0]


def _indexes(t: np.ndarray, rep: np.ndarray) -> list[rr.TimeColumn]:
    return [rr.TimeColumn(SIM_TIME, duration=np.asarray(t, dtype=float)),
            rr.TimeColumn(REPETITION, sequence=np.asarray(rep, dtype=np.int64))]
