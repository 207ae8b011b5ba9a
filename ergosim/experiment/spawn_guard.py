"""Worker processes are spawned, and a spawned process imports the main script again: a script that starts
a parallel run from its top level, outside ``if __name__ == "__main__":``, would run it again in every
worker. Python then stops the workers with a RuntimeError that reaches the caller as ``BrokenProcessPool``.
:func:`check_main_guard` finds that case before any process starts and says how to fix it.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["check_main_guard"]


def _guarded_lines(tree: ast.Module) -> list[tuple[int, int]]:
    """(first, last) lines of the bodies of the module-level ``if __name__ == "__main__":`` blocks."""
    spans = []
    for node in tree.body:
        test = node.test if isinstance(node, ast.If) else None
        if isinstance(test, ast.Compare) and len(test.comparators) == 1:
            names = {ast.unparse(test.left), ast.unparse(test.comparators[0])}
            if names == {"__name__", "'__main__'"} and isinstance(test.ops[0], ast.Eq):
                spans.append((node.body[0].lineno, node.body[-1].end_lineno or node.body[-1].lineno))
    return spans


def check_main_guard(where: str) -> None:
    """Raise a ConfigError if the main script is calling, from its top level and outside ``if __name__ ==
    "__main__":``, the function that is about to spawn worker processes. Interactive sessions, ``-c`` and
    ``-m`` modules with a guard, and callers inside functions pass."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if not path or not Path(path).is_file():
        return
    frame = sys._getframe(1)
    while frame is not None and not (frame.f_code.co_name == "<module>"
                                     and frame.f_globals.get("__name__") == "__main__"):
        frame = frame.f_back
    if frame is None:
        return
    try:
        tree = ast.parse(Path(path).read_text(encoding="utf-8"))
    except (OSError, SyntaxError, UnicodeDecodeError, ValueError):
        return
    line = frame.f_lineno
    if any(first <= line <= last for first, last in _guarded_lines(tree)):
        return
    raise ConfigError(f"{Path(path).name} line {line} starts worker processes from the script's top level; "
                      "each worker imports the script again and would start them again: put the run under "
                      "`if __name__ == \"__main__\":` (or run with jobs=1)", where=where)
