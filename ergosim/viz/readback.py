"""Read a twin recording back with rerun's own chunk reader (tests, and checks against ``ticks.csv``)."""

from __future__ import annotations

import os
from collections import defaultdict

import numpy as np
import pyarrow as pa
from rerun.chunk import RrdReader

from ergosim.viz.paths import SIM_TIME

__all__ = ["RecordingReader"]


class RecordingReader:
    """All chunks of the first recording in an .rrd file, grouped by entity path (without the leading /)."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        reader = RrdReader(path)
        self.application_ids = [s.application_id for s in reader.recordings()]
        self.has_blueprint = bool(reader.blueprints())
        self._chunks: dict[str, list[pa.RecordBatch]] = defaultdict(list)
        self._static: dict[str, list[pa.RecordBatch]] = defaultdict(list)
        for chunk in reader.stream().to_chunks():
            target = self._static if chunk.is_static else self._chunks
            target[chunk.entity_path.lstrip("/")].append(chunk.to_record_batch())

    @property
    def entities(self) -> set[str]:
        """Every entity path that holds data, static or temporal."""
        return set(self._chunks) | set(self._static)

    def components(self, entity: str, *, static: bool = False) -> set[str]:
        """Component column names (``"Archetype:field"``) present at ``entity``."""
        batches = (self._static if static else self._chunks).get(entity, [])
        return {name for b in batches for name in b.schema.names if ":" in name}

    def column(self, entity: str, component: str, *, timeline: str = SIM_TIME
               ) -> tuple[np.ndarray, list]:
        """(times (n,), values (n,)) of ``component`` at ``entity`` sorted by ``timeline``; a duration
        timeline comes back in seconds. Each value is the row's list of instances."""
        times, values = [], []
        for batch in self._chunks.get(entity, []):
            names = batch.schema.names
            if component not in names or timeline not in names:
                continue
            t = batch.column(names.index(timeline))
            if pa.types.is_duration(t.type):
                times.append(t.cast(pa.int64()).to_numpy(zero_copy_only=False) / _DURATION_PER_S[t.type.unit])
            else:
                times.append(t.to_numpy(zero_copy_only=False))
            values.extend(batch.column(names.index(component)).to_pylist())
        if not times:
            raise KeyError(f"{entity} has no {component} on timeline {timeline}")
        t = np.concatenate(times)
        order = np.argsort(t, kind="stable")
        return t[order], [values[i] for i in order]

    def scalars(self, entity: str, *, timeline: str = SIM_TIME) -> tuple[np.ndarray, np.ndarray]:
        """(times (n,), values (n,)) of the Scalars series at ``entity``."""
        t, rows = self.column(entity, "Scalars:scalars", timeline=timeline)
        return t, np.array([r[0] for r in rows], dtype=float)

    def transforms(self, entity: str, *, timeline: str = SIM_TIME
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(times (n,), translations (n, 3) [m], quaternions (n, 4) xyzw) logged at ``entity``."""
        t, trans = self.column(entity, "Transform3D:translation", timeline=timeline)
        _, quat = self.column(entity, "Transform3D:quaternion", timeline=timeline)
        return t, np.array([r[0] for r in trans], dtype=float), np.array([r[0] for r in quat], dtype=float)

    def texts(self, entity: str, *, timeline: str = SIM_TIME) -> tuple[np.ndarray, list[str]]:
        t, rows = self.column(entity, "TextLog:text", timeline=timeline)
        return t, [r[0] for r in rows]

    def static(self, entity: str, component: str) -> list:
        """The instances of a static ``component`` at ``entity`` (last write wins)."""
        found = None
        for batch in self._static.get(entity, []):
            if component in batch.schema.names:
                found = batch.column(batch.schema.names.index(component)).to_pylist()[-1]
        if found is None:
            raise KeyError(f"{entity} has no static {component}")
        return found


_DURATION_PER_S = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9}
