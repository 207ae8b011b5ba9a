"""Modules of another git revision of this repository, loaded beside this checkout's: the side-by-side
benchmarks (``--baseline REV`` of ``scripts/bench_planner.py --lookahead`` and ``scripts/bench_ik.py``) time
the old and the new code in one process, call by call, so that both see the same machine load (the only fair
speed ratio on a shared machine). :func:`tree_at` copies a folder of files as another revision has them (the
models, for ``scripts/bench_video.py --baseline``)."""

from __future__ import annotations

import io
import re
import subprocess
import sys
import tarfile
import types
from collections.abc import Sequence
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["modules_at", "tree_at"]

ROOT = Path(__file__).resolve().parents[1]


def modules_at(rev: str, package: str, names: Sequence[str]) -> dict[str, types.ModuleType]:
    """Modules ``names`` of ``package`` (e.g. ``"ergosim.planner"``; in import order: each imports only
    earlier ones among them) as git revision ``rev`` has them, read with ``git show`` and executed under
    private module names, their imports of one another redirected to those copies. Everything else they
    import is this checkout's, so both revisions work on the same objects.

    Raises:
        ConfigError: ``rev`` is not a revision of the repository, or lacks one of the modules.
    """
    tag = re.sub(r"\W", "_", rev)
    private = {m: f"_rev_{tag}_{package.replace('.', '_')}_{m}" for m in names}
    pattern = re.compile(rf"\b{re.escape(package)}\.({'|'.join(map(re.escape, names))})\b")
    folder = package.replace(".", "/")
    mods = {}
    for m in names:
        path = f"{folder}/{m}.py"
        out = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{path}"], check=False,
                             capture_output=True, text=True)
        if out.returncode:
            raise ConfigError(f"cannot read {path} at revision {rev!r}: {out.stderr.strip()}",
                              where="--baseline")
        mod = types.ModuleType(private[m])
        sys.modules[mod.__name__] = mod  # dataclasses look their module up by name
        src = pattern.sub(lambda hit: private[hit.group(1)], out.stdout)
        exec(compile(src, f"{rev}:{path}", "exec"), mod.__dict__)  # noqa: S102 - our own code, at rev
        mods[m] = mod
    return mods


def tree_at(rev: str, folder: str, dest: str | Path) -> Path:
    """Write ``folder`` of the repository (e.g. ``"models"``) as git revision ``rev`` has it under ``dest``;
    returns ``dest / folder``.

    Raises:
        ConfigError: ``rev`` is not a revision of the repository, or has no ``folder``.
    """
    out = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", rev, folder], check=False,
                         capture_output=True)
    if out.returncode:
        raise ConfigError(f"cannot read {folder}/ at revision {rev!r}: {out.stderr.decode().strip()}",
                          where="--baseline")
    with tarfile.open(fileobj=io.BytesIO(out.stdout)) as tar:
        tar.extractall(dest, filter="data")
    return Path(dest) / folder
