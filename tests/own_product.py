"""A user's own product and workcell, written into a test's folder: no bundled file is involved.

A small bracket: a base block is put into a fixture, a pin is inserted and a screw fastened into it, the
assembly goes to an outfeed tray, and from there it is handed to a second operator (a receiver outside the
cell) at a pose in the air. Every action kind of the vocabulary appears once; both agents may do every
action, so a test can have the same operation done by the worker and by the robot.
"""

from __future__ import annotations

from pathlib import Path

TASK = """
name = "bracket"
description = "A base block, a pin and a screw"
parts = ["fixture", "base", "pin", "screw", "tray", "away"]

[agents.human]
kind = "human"
[agents.robot]
kind = "robot"
cost = 2.5

[[liaisons]]
parts = ["fixture", "base"]
action = "b1"
[[liaisons]]
parts = ["base", "pin"]
action = "b2"
[[liaisons]]
parts = ["base", "screw"]
action = "b3"
[[liaisons]]
parts = ["base", "tray"]
action = "b4"
[[liaisons]]
parts = ["base", "away"]
action = "b5"

[[precedence]]
before = "b1"
after = ["b2", "b3"]
[[precedence]]
before = ["b2", "b3"]
after = ["b4"]
[[precedence]]
before = "b4"
after = ["b5"]
"""

CELL = """
name = "bracket-cell"
description = "A bench with the Panda on its far edge"
carry_height = 1.15

[worker]
xy = [0.0, 0.0]
hand = "right"

[robots.robot]
base = [0.90, 0.05, 0.9]
yaw = 180.0
support = "bench"

[furniture.bench]
type = "table"
center = [0.62, 0.0]
size = [0.64, 1.0]
height = 0.9

[parts.base]
shape = "box"
size = [0.06, 0.06, 0.04]
mass = 0.2
xy = [0.55, 0.20]
insert_axis = "z"

[[parts.base.slots]]
name = "pin_hole"
at = [0.015, 0.0, 0.0]
axis = "z"

[[parts.base.slots]]
name = "screw_hole"
at = [-0.015, 0.0, 0.0]
axis = "z"

[parts.pin]
shape = "cylinder"
radius = 0.006
length = 0.05
density = 7850.0
xy = [0.50, 0.28]
insert_axis = "z"

[parts.screw]
shape = "cylinder"
radius = 0.004
length = 0.03
density = 7850.0
xy = [0.60, 0.30]
insert_axis = "z"
grasp = "top"

[targets.fixture]
on = "bench"
xy = [0.45, 0.0]
part = "base"

[targets.tray]
on = "bench"
xy = [0.48, -0.25]
part = "base"

[targets.second_operator]
pos = [0.50, -0.30, 1.15]

[actions.b1]
kind = "place"
part = "base"
target = "fixture"

[actions.b2]
kind = "insert"
part = "pin"
target = "base.pin_hole"

[actions.b3]
kind = "fasten"
part = "screw"
target = "base.screw_hole"
turn_time = 1.0

[actions.b4]
kind = "remove"
part = "base"
target = "tray"

[actions.b5]
kind = "handover"
part = "base"
target = "second_operator"

[aliases]
base_xy = "parts.base.xy"
"""

SCENARIO = """
name = "bracket"
description = "The bracket in its cell"
task = "bracket_task.toml"
workcell = "bracket_cell.toml"

[protocol]
subjects = 1
repetitions = 1
modes = ["hrc", "h-only", "r-only"]
robot_cost = 2.5
takt = 60.0
"""


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
