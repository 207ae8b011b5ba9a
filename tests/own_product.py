"""A user's own product and workcell, written into a test's folder: no bundled file is involved.

The files are those of ``examples/own_workcell``, the README's walk-through, so CI runs what it shows.

A small bracket: a base block is put into a fixture, a pin is inserted and a screw fastened into it, the
assembly goes to an outfeed tray, and from there it is handed to a second operator (a receiver outside the
cell) at a pose in the air. Every action kind of the vocabulary appears once; both agents may do every
action, so a test can have the same operation done by the worker and by the robot.
"""

from __future__ import annotations

from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "own_workcell"
TASK = (EXAMPLE / "bracket_task.toml").read_text()
CELL = (EXAMPLE / "bracket_cell.toml").read_text()
SCENARIO = (EXAMPLE / "bracket.toml").read_text()
"""The files of examples/own_workcell (the README's "Your own workcell"), as text to vary in tests."""


def write_product(folder: Path, *, task: str = TASK, cell: str = CELL, scenario: str = SCENARIO) -> Path:
    """Write the task, the workcell and the scenario file into ``folder``; return the scenario's path."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "bracket_task.toml").write_text(task)
    (folder / "bracket_cell.toml").write_text(cell)
    path = folder / "bracket.toml"
    path.write_text(scenario)
    return path


def two_robots(task: str = TASK, cell: str = CELL) -> tuple[str, str]:
    """The bracket with a second Panda, ``robot2``, on the bench's right: the task lets it (and not
    ``robot``) insert the pin, b2."""
    task = task.replace('cost = 2.5\n', 'cost = 2.5\n[agents.robot2]\nkind = "robot"\ncost = 2.6\n', 1)
    task = task.replace('parts = ["base", "pin"]\naction = "b2"\n',
                        'parts = ["base", "pin"]\naction = "b2"\nagents = ["human", "robot2"]\n')
    cell = cell.replace("[furniture.bench]", '[robots.robot2]\nbase = [0.90, -0.35, 0.9]\nyaw = 180.0\n'
                        'support = "bench"\n\n[furniture.bench]')
    return task, cell


def write_block_stl(path: Path, half=(0.02, 0.02, 0.015)) -> None:
    """A binary STL of a box of half sizes ``half`` [m] centred on its origin (12 triangles)."""
    import numpy as np  # noqa: PLC0415

    h = np.asarray(half, dtype=float)
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * h
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6),
             (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    for i, f in enumerate(faces):
        a, b, c = v[list(f)]
        n = np.cross(b - a, c - a)
        rec[i]["n"], rec[i]["v"] = n / np.linalg.norm(n), (a, b, c)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"\0" * 80 + np.uint32(len(faces)).tobytes() + rec.tobytes())
