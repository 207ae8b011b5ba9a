"""The command line's contract: one-line errors, quiet exits."""

from __future__ import annotations

import subprocess
import sys


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


def test_unknown_command_is_a_usage_error():
    proc = subprocess.run([sys.executable, "-m", "ergosim.cli", "frobnicate"], check=False,
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "invalid choice: 'frobnicate'" in proc.stderr
