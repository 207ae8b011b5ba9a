"""The ``ergosim`` command line.

Each subcommand lives in ``ergosim/commands/<name>.py`` and exposes ``add_parser(subparsers)`` and
``run(args) -> int``. Every subcommand takes ``--verbose`` (diagnostics at DEBUG: what is read, written and
finished) and ``--quiet`` (only warnings; no progress bar), :mod:`ergosim.logs`. Errors from the
:class:`~ergosim.errors.ErgosimError` family are printed as one line on stderr with exit status 2, never as a
traceback. ``ergosim run`` exits 3 when a repetition was
abandoned, and 128 + N when signal N (SIGINT, SIGTERM) stopped it.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import sys

from ergosim import __version__
from ergosim.errors import ErgosimError, one_line_warnings
from ergosim.logs import configure

__all__ = ["main", "build_parser"]

COMMANDS = ("plan", "run", "scenarios", "replay", "render", "export", "plot", "report", "fidelity", "sweep",
            "compare", "merge")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ergosim",
        description="Digital twin of ergonomic human-robot role allocation (Merlo, Lamon et al.).",
    )
    parser.add_argument("--version", action="version", version=f"ergosim {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f"ergosim.commands.{name}")
        sp = module.add_parser(sub)
        sp.set_defaults(_run=module.run)
        _add_log_options(sp)
    return parser


def _add_log_options(p: argparse.ArgumentParser) -> None:
    """``--verbose`` and ``--quiet`` on every subcommand (a command's own ``--quiet`` says what else it
    leaves out)."""
    group = p.add_argument_group("diagnostics")
    group.add_argument("-v", "--verbose", action="store_true",
                       help="log what is read, written and finished (to stderr)")
    if "--quiet" not in p._option_string_actions:
        group.add_argument("-q", "--quiet", action="store_true", help="log warnings only")


def _log_level(args: argparse.Namespace) -> int:
    if args.verbose:
        return logging.DEBUG
    return logging.WARNING if getattr(args, "quiet", False) else logging.INFO


def headless_gl() -> None:
    """Pick MuJoCo's offscreen EGL on a Linux machine without a display (MUJOCO_GL is read when mujoco is
    imported, so this runs first); an explicit MUJOCO_GL, or a display, wins."""
    if ("MUJOCO_GL" not in os.environ and sys.platform.startswith("linux") and "mujoco" not in sys.modules
            and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY")):
        os.environ["MUJOCO_GL"] = "egl"


def main(argv: list[str] | None = None) -> int:
    headless_gl()
    one_line_warnings()
    parser = build_parser()
    args = parser.parse_args(argv)
    configure(_log_level(args))
    try:
        return int(args._run(args) or 0)
    except ErgosimError as err:
        print(f"ergosim: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:  # Ctrl-C, or SIGTERM during a run (ergosim.experiment.interrupt)
        signum = getattr(err, "signum", 2)
        print(f"ergosim: interrupted{' by SIGTERM' if signum == 15 else ''}", file=sys.stderr)
        return 128 + signum
    except BrokenPipeError:
        # the reader of stdout went away (e.g. `ergosim plan ... | head`): stop quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
