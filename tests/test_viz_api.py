"""The public API of ergosim.viz, and the blueprint every recording carries."""

from __future__ import annotations

import importlib

from rerun.chunk import RrdReader

import ergosim.viz
from ergosim.viz import open_recording


def test_every_public_name_exists():
    module = importlib.import_module("ergosim.viz")
    assert module.__all__, "ergosim.viz must export its API"
    for name in module.__all__:
        assert getattr(module, name) is not None, name
    assert {"TwinRecorder", "open_recording", "allocation_reason"} <= set(ergosim.viz.__all__)


def test_blueprint_has_the_panels_of_issue_7(tmp_path):
    path = tmp_path / "empty.rrd"
    open_recording(rrd=path).close()
    reader = RrdReader(path)
    (store,) = reader.blueprints()
    names, origins = [], []
    for chunk in reader.stream(store=store).to_chunks():
        batch = chunk.to_record_batch()
        for column, out in (("ViewBlueprint:display_name", names), ("ViewBlueprint:space_origin", origins)):
            if column in batch.schema.names:
                out.extend(row[0] for row in batch.column(batch.schema.names.index(column)).to_pylist())
    assert sorted(names) == sorted(["Workcell", "KWear V(t) and V_th", "RULA", "Arm angles [deg]",
                                    "Trunk & neck angles [deg]", "Decisions and failures",
                                    "Predicted KWear V̂", "Hyper-arc costs"])
    assert {"world", "ergonomics/rula", "ergonomics/angles", "allocation/log"} <= set(origins)
