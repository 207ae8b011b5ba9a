"""Sink arguments (--rrd, --spawn, --connect) and the atomic .rrd file. Nothing here opens a viewer or a
network connection: spawn and connect are exercised only as argument handling."""

from __future__ import annotations

import os

import numpy as np
import pytest

from ergosim.errors import ConfigError
from ergosim.viz import DEFAULT_URL, RecordingReader, open_recording, plan_sinks


def test_nothing_requested_gives_a_no_op_recorder(tmp_path):
    plan = plan_sinks()
    assert plan.empty and plan.urls == () and plan.rrd is None
    rec = open_recording()
    assert not rec.enabled
    rec.log_ticks(0, np.zeros(2), np.zeros((2, 1, 3)), np.zeros((2, 1, 4)), ["b"], np.zeros((2, 14)),
                  np.zeros((2, 7)), np.zeros(2), np.zeros((2, 5)))
    rec.log_decision(0.0, 0, np.zeros(5), {}, {}, ("a1", "human"), "a1 → human")
    rec.close()
    rec.close()


def test_connect_and_spawn_urls():
    assert plan_sinks(connect="default").urls == (DEFAULT_URL,)
    assert plan_sinks(spawn=True).urls == (DEFAULT_URL,)
    # spawning and connecting to the same viewer is one sink, not two
    assert plan_sinks(spawn=True, connect="default").urls == (DEFAULT_URL,)
    other = "rerun+http://10.0.0.7:9877/proxy"
    plan = plan_sinks(spawn=True, connect=other)
    assert plan.spawn and plan.urls == (DEFAULT_URL, other)


@pytest.mark.parametrize("url", ["http://127.0.0.1:9876", "127.0.0.1:9876", "rerun+http://host:9876/data"])
def test_a_url_rerun_cannot_use_is_a_config_error(url):
    with pytest.raises(ConfigError, match="--connect: cannot stream to") as err:
        plan_sinks(connect=url)
    assert "\n" not in str(err.value)


def test_rrd_path_that_is_a_directory_is_a_config_error(tmp_path):
    with pytest.raises(ConfigError, match="--rrd: .* is a directory"):
        plan_sinks(rrd=tmp_path)


def _siblings(path):
    return sorted(p.name for p in path.parent.iterdir())


def test_rrd_appears_under_its_name_only_when_closed(tmp_path):
    target = tmp_path / "out" / "run.rrd"
    rec = open_recording(rrd=target, recording_name="subject 1")
    assert rec.enabled and not target.exists()
    (tmp,) = _siblings(target)
    assert tmp.startswith(".run.rrd.") and tmp.endswith(".tmp")
    rec.close()
    assert _siblings(target) == ["run.rrd"]
    mask = os.umask(0)
    os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~mask
    reader = RecordingReader(target)
    assert reader.application_ids == ["ergosim"] and reader.has_blueprint


def test_an_exception_inside_with_leaves_no_file(tmp_path):
    target = tmp_path / "run.rrd"
    with pytest.raises(RuntimeError, match="loop failed"), open_recording(rrd=target) as rec:
        assert rec.enabled
        raise RuntimeError("loop failed")
    assert list(tmp_path.iterdir()) == []
