"""The command line's contract: one-line errors, quiet exits."""

from __future__ import annotations

import subprocess
import sys

import pytest


@pytest.mark.slow
def test_a_closed_stdout_ends_quietly():
    """`ergosim plan ... | head` closing the pipe early is not an error worth a traceback."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "ergosim.cli", "plan", "--generate", "sequential:12", "--agents", "3"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    proc.stdout.close()  # before the child, still importing, writes anything
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=60) in (0, 141)
    assert "Traceback" not in err and "BrokenPipe" not in err, err


@pytest.mark.slow
def test_unknown_command_is_a_usage_error():
    proc = subprocess.run([sys.executable, "-m", "ergosim.cli", "frobnicate"], check=False,
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "invalid choice: 'frobnicate'" in proc.stderr


def test_every_command_takes_verbose_and_quiet_and_diagnostics_go_through_logging(capsys):
    import argparse  # noqa: PLC0415
    import logging  # noqa: PLC0415

    from ergosim.cli import COMMANDS, build_parser  # noqa: PLC0415
    from ergosim.logs import configure, configured_level  # noqa: PLC0415

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name in COMMANDS:
        options = sub.choices[name]._option_string_actions
        assert {"-v", "--verbose", "-q", "--quiet"} <= set(options), name
    logger = logging.getLogger("ergosim.experiment.run_merge")
    try:
        for level in (logging.DEBUG, logging.INFO, logging.WARNING):
            configure(level)
            configure(level)  # once, however often
            logger.debug("a diagnostic")
            logger.info("a note")
            logger.warning("a problem")
            assert configured_level() == level
        err = capsys.readouterr().err.splitlines()
        assert err == ["DEBUG ergosim.experiment.run_merge: a diagnostic",
                       "INFO ergosim.experiment.run_merge: a note",
                       "WARNING ergosim.experiment.run_merge: a problem",
                       "a note", "a problem", "a problem"]
    finally:
        configure(logging.INFO)
