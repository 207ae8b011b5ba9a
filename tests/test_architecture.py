"""The package's architecture, checked (issue 25): checks that fail when the layering breaks.

Imports are read with :mod:`ast` from every module of ``ergosim/``, function-level imports included (a
lazy ``from ergosim.viz import ...`` inside a function is an import all the same). The layers and what each
holds are drawn in docs/architecture.md. Each allowance below names a known exception, with the reason and
the issue that removes it; an allowance that no longer matches anything fails too, so the lists only shrink.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "ergosim"

# The layers, lowest first: a module may import its own layer and the layers below, never one above.
LAYERS: tuple[tuple[str, ...], ...] = (
    # 0 foundation: errors, file writing, registries, the schema of the file formats, logging
    ("__init__", "errors", "atomic", "registry", "plugins", "logs", "overrides", "schema", "posture",
     "progress", "exports", "quat", "machine", "held_signals", "g9_csv", "blas_kernel"),
    # 1 the models: body, risk, robot, worker motion, task planning, workcells
    ("human", "ergonomics", "robot", "worker", "planner", "scenes"),
    # 2 the simulation: loop, sessions, allocators, tracks
    ("twin",),
    # 3 pictures of the simulation: rerun recordings, video, the colours the figures share with them
    ("viz", "video", "colors"),
    # 4 the experiment around the simulation: scenarios, runs, outputs, merge, summaries
    ("experiment",),
    # 5 studies made of experiments
    ("fidelity", "sweep"),
    # 6 the user's entry points (gym: the Gymnasium environment, built on api)
    ("api", "commands", "cli", "gym"),
)
SIMULATION = ("twin", "worker", "robot", "planner", "ergonomics", "scenes")
PRESENTATION = ("experiment", "video", "viz")

# (module, imported package) -> why it is allowed for now
LAYER_ALLOWANCES: dict[tuple[str, str], str] = {}
# module -> (its line count cap, why it is one concept)
MODULE_LINES = 400
MODULE_ALLOWANCES = {
    "ergosim/sweep/design.py": (503, "one file format: a sweep file's axes, designs and cells"),
}
# import circles allowed for now: the modules of each, and why
CIRCLE_ALLOWANCES: dict[frozenset[str], str] = {}
# (module, function) -> its line count cap
FUNCTION_LINES = 80
FUNCTION_ALLOWANCES: dict[tuple[str, str], int] = {}
# module -> the number of reads of a graph's private attributes it may still make
GRAPH_PRIVATE_ALLOWANCES: dict[str, int] = {}


# -- reading the package -------------------------------------------------------------------------------------
@functools.cache
def _modules() -> dict[str, ast.Module]:
    return {p.relative_to(ROOT).as_posix(): ast.parse(p.read_text(encoding="utf-8"), str(p))
            for p in sorted(PACKAGE.rglob("*.py"))}


def _package_of(rel: str) -> str:
    """``ergosim/twin/loop.py`` -> ``twin``; ``ergosim/cli.py`` -> ``cli``."""
    return Path(rel).parts[1].removesuffix(".py")


def _imports(rel: str, tree: ast.Module) -> list[tuple[int, str]]:
    """(line, imported ergosim module) of every import in the module, at any depth, relative ones resolved."""
    package = Path(rel).parts[:-1]  # a module's package; an __init__.py's is its own
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = ".".join(package[:len(package) - node.level + 1])
                module = f"{base}.{node.module}" if node.module else base
            else:
                module = node.module or ""
            out.append((node.lineno, module))
            out += [(node.lineno, f"{module}.{a.name}") for a in node.names]  # `from ergosim import viz`
    return [(line, m) for line, m in out if m == "ergosim" or m.startswith("ergosim.")]


def _imported_packages(rel: str, tree: ast.Module) -> dict[str, int]:
    """Top-level ergosim packages (or modules) the module imports -> the first line that does."""
    names = {p.stem for p in PACKAGE.iterdir() if p.suffix == ".py" or (p / "__init__.py").is_file()}
    found: dict[str, int] = {}
    for line, module in _imports(rel, tree):
        parts = module.split(".")
        if len(parts) > 1 and parts[1] in names:
            found.setdefault(parts[1], line)
    return found


def _layer(package: str) -> int:
    return next(i for i, layer in enumerate(LAYERS) if package in layer)


# -- the import layers ---------------------------------------------------------------------------------------
@pytest.mark.slow
def test_every_package_has_a_layer():
    packages = {_package_of(rel) for rel in _modules()}
    missing = sorted(p for p in packages if not any(p in layer for layer in LAYERS))
    assert missing == [], f"add these to a layer in LAYERS (and docs/architecture.md): {missing}"


@pytest.mark.slow
def test_the_simulation_never_imports_the_experiment_video_or_viz():
    found = [f"{rel}:{line} imports ergosim.{pkg}" for rel, tree in _modules().items()
             if _package_of(rel) in SIMULATION
             for pkg, line in _imported_packages(rel, tree).items() if pkg in PRESENTATION]
    assert found == []


def test_no_package_imports_a_higher_layer():
    found, used = [], set()
    for rel, tree in _modules().items():
        own = _layer(_package_of(rel))
        for pkg, line in _imported_packages(rel, tree).items():
            if pkg in LAYERS[0] or _layer(pkg) <= own:
                continue
            if (rel, pkg) in LAYER_ALLOWANCES:
                used.add((rel, pkg))
                continue
            found.append(f"{rel}:{line} (layer {own}) imports ergosim.{pkg} (layer {_layer(pkg)})")
    assert found == []
    assert sorted(set(LAYER_ALLOWANCES) - used) == [], "allowances no longer needed: remove them"


def test_the_import_reader_sees_function_level_and_relative_imports():
    """The checks above can fail: the reader finds an import inside a function and a relative one."""
    src = ("import numpy\n"
           "def f():\n"
           "    from ergosim.viz import reason_text\n"
           "    import ergosim.video.frames\n"
           "from ..experiment import runner\n"
           "from ergosim import sweep\n")
    found = _imported_packages("ergosim/twin/x.py", ast.parse(src))
    assert found == {"viz": 3, "video": 4, "experiment": 5, "sweep": 6}


# -- one place builds a session ----------------------------------------------------------------------------
def _imported_modules(rel: str) -> set[str]:
    return {m for _, m in _imports(rel, _modules()[rel])}


def test_the_api_and_the_gym_build_their_sessions_with_the_twins_rig():
    """A session is built in ``twin/rig.py``: the Python API and the Gym environment never import the
    experiment's runner, and the experiment's subject sessions, its runner and the Gym environment call the
    rig."""
    users = ["ergosim/api.py", *sorted(r for r in _modules() if r.startswith("ergosim/gym/"))]
    assert [r for r in users if "ergosim.experiment.runner" in _imported_modules(r)] == []
    for rel in ("ergosim/experiment/subject.py", "ergosim/experiment/runner.py", "ergosim/gym/env.py"):
        assert any(m.startswith("ergosim.twin.rig") for m in _imported_modules(rel)), rel


# -- the package is what a user imports ------------------------------------------------------------------
def _third_party_imports(tree: ast.Module) -> set[str]:
    out = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    out |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module and not n.level}
    return {m.split(".")[0] for m in out}


def test_no_benchmark_or_study_module_lives_in_the_package():
    """Benchmarks and studies live in ``benchmarks/`` beside the package (mink keeps its benchmarks out of
    ``mink/``): no module of ``ergosim/`` is named for one, none imports ``benchmarks``, and the planner
    draws nothing."""
    words = ("benchmark", "revision", "study")
    named = [rel for rel in _modules() if any(w in Path(rel).stem for w in words)]
    assert named == []
    assert [rel for rel, tree in _modules().items() if "benchmarks" in _third_party_imports(tree)] == []
    planner = {rel: tree for rel, tree in _modules().items() if rel.startswith("ergosim/planner/")}
    assert planner and [rel for rel, t in planner.items() if "matplotlib" in _third_party_imports(t)] == []
    assert (ROOT / "benchmarks" / "planner.py").is_file()  # where they went


# -- no import circle -------------------------------------------------------------------------------------
def _module_name(rel: str) -> str:
    """``ergosim/twin/loop.py`` -> ``ergosim.twin.loop``; ``ergosim/twin/__init__.py`` -> ``ergosim.twin``."""
    return ".".join(Path(rel).with_suffix("").parts).removesuffix(".__init__")


@functools.cache
def _import_graph() -> dict[str, frozenset[str]]:
    """Module -> the package modules it imports, at any depth (function-level and ``TYPE_CHECKING`` imports
    included: a type is a dependency too). ``from p import name`` is an import of ``p.name`` when that is a
    module, else of ``p``."""
    names = {_module_name(rel) for rel in _modules()}
    graph = {}
    for rel, tree in _modules().items():
        own, out = _module_name(rel), set()
        by_line: dict[int, list[str]] = {}
        for line, m in _imports(rel, tree):
            by_line.setdefault(line, []).append(m)
        for found in by_line.values():  # one import statement
            for m in found:
                if m in names and not any(f.startswith(m + ".") and f in names for f in found):
                    out.add(m)
                elif m not in names and m.rsplit(".", 1)[0] in names:
                    out.add(m.rsplit(".", 1)[0])
        graph[own] = frozenset(out - {own})
    return graph


def _circles(graph: dict[str, frozenset[str]]) -> list[frozenset[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iteratively)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out = []
    for root, edges in graph.items():
        if root in index:
            continue
        work = [(root, iter(sorted(edges)))]
        index[root] = low[root] = len(index)
        stack.append(root)
        while work:
            v, todo = work[-1]
            w = next(todo, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                elif w in stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                part = set()
                while True:
                    w = stack.pop()
                    part.add(w)
                    if w == v:
                        break
                if len(part) > 1:
                    out.append(frozenset(part))
    return out


def test_no_import_circle():
    found = _circles(_import_graph())
    assert [sorted(c) for c in found if c not in CIRCLE_ALLOWANCES] == []
    assert [sorted(c) for c in CIRCLE_ALLOWANCES if c not in found] == [], "allowance no longer needed"


def test_the_circle_finder_finds_them():
    graph = {"a": frozenset({"b"}), "b": frozenset({"c"}), "c": frozenset({"a", "d"}), "d": frozenset(),
             "e": frozenset({"e2"}), "e2": frozenset({"e"}), "f": frozenset({"a"})}
    assert sorted(map(sorted, _circles(graph))) == [["a", "b", "c"], ["e", "e2"]]
    assert _import_graph()["ergosim.twin.catalogue"] >= {"ergosim.twin.modes",
                                                         "ergosim.twin.lookahead_allocator"}


# -- a posture feature is a registered thing -----------------------------------------------------------
FEATURE_USERS = ("ergosim/twin/features.py", "ergosim/twin/loop.py", "ergosim/twin/calibration.py",
                 "ergosim/twin/worker_track.py", "ergosim/twin/rig.py")


def test_the_twin_switches_on_no_posture_feature_by_name():
    """The twin scores, logs and calibrates every feature through its registered hook: the modules that do
    it name no feature but the paper's base, ``rula`` (so a new feature touches none of them)."""
    from ergosim.ergonomics.features import FEATURES  # noqa: PLC0415

    others = set(FEATURES) - {"rula"}
    found = {rel: sorted({n.value for n in ast.walk(_modules()[rel])
                          if isinstance(n, ast.Constant) and n.value in others}) for rel in FEATURE_USERS}
    assert {rel: names for rel, names in found.items() if names} == {}
    assert {"reba", "angles"} <= others


# -- composition, not overriding -----------------------------------------------------------------------
def test_no_class_extends_the_session():
    """Parallel execution is a strategy the session calls (``twin/team_session.py``,
    ``ParallelExecution``), not a subclass of ``Session`` overriding its private methods."""
    subclasses = [f"{rel}:{node.name}" for rel, tree in _modules().items() for node in ast.walk(tree)
                  if isinstance(node, ast.ClassDef)
                  and any(ast.unparse(b).split(".")[-1] == "Session" for b in node.bases)]
    assert subclasses == []


# -- the planner graph's private state --------------------------------------------------------------------
@functools.cache
def _graph_private_names() -> frozenset[str]:
    """Private attributes the planner's graph classes set on ``self``."""
    names = set()
    for rel, tree in _modules().items():
        if not rel.startswith("ergosim/planner/"):
            continue
        for cls in (n for n in ast.walk(tree) if isinstance(n, ast.ClassDef) and n.name.endswith("Graph")):
            for node in ast.walk(cls):
                if (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store)
                        and isinstance(node.value, ast.Name) and node.value.id == "self"
                        and node.attr.startswith("_") and not node.attr.startswith("__")):
                    names.add(node.attr)
    return frozenset(names)


def _graph_private_reads(tree: ast.Module, private: frozenset[str]) -> list[str]:
    """``x._name`` where ``x`` is not ``self`` / ``cls`` and either names a graph (``graph``, ``self.graph``,
    ``task_graph``) or ``_name`` is an attribute a graph class keeps private."""
    out = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute) or not node.attr.startswith("_") or node.attr.startswith("__"):
            continue
        value = node.value
        if isinstance(value, ast.Name) and value.id in ("self", "cls"):
            continue
        last = getattr(value, "attr", None) or getattr(value, "id", None) or ""
        if "graph" in last.lower() or node.attr in private:
            out.append((node.lineno, ast.unparse(node)))
    return [f"{line} {text}" for line, text in sorted(out)]


def test_no_code_outside_the_planner_reads_a_graphs_private_attributes():
    private = _graph_private_names()
    counts = {rel: _graph_private_reads(tree, private) for rel, tree in _modules().items()
              if not rel.startswith("ergosim/planner/")}
    found = {rel: reads for rel, reads in counts.items() if reads and rel not in GRAPH_PRIVATE_ALLOWANCES}
    assert found == {}
    for rel, allowed in GRAPH_PRIVATE_ALLOWANCES.items():
        n = len(counts.get(rel, []))
        assert n <= allowed, f"{rel} reads a graph's private attributes more often ({n} > {allowed})"
        assert n == allowed, f"{rel} now makes {n} private reads: lower (or remove) its allowance"


def test_the_private_read_finder_finds_them():
    src = ("def join(graph, board, op):\n"
           "    a = graph._op_index[op]\n"
           "    b = board.graph._node_masks\n"
           "    c = self._graph._layout\n"
           "    d = other._part_index\n"
           "    return self._cache, graph.nodes\n")
    reads = _graph_private_reads(ast.parse(src), frozenset({"_part_index"}))
    assert reads == ["2 graph._op_index", "3 board.graph._node_masks", "4 self._graph._layout",
                     "5 other._part_index"]


# -- one list of outputs -------------------------------------------------------------------------------------
def _imported_names(tree: ast.Module) -> set[tuple[str, str]]:
    return {(node.module, a.name) for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and node.module for a in node.names}


def test_run_merge_and_sweep_write_through_the_one_outputs_list():
    """``ergosim run``, ``ergosim merge`` and a sweep's units reach a run folder's files only through
    :data:`ergosim.experiment.outputs.OUTPUTS`; the file writers behind it are imported by outputs.py
    alone."""
    mods = _modules()
    lists = "ergosim.experiment.outputs"
    assert (lists, "write_outputs") in _imported_names(mods["ergosim/experiment/scenario_run.py"])
    assert (lists, "merge_outputs") in _imported_names(mods["ergosim/experiment/run_merge.py"])
    assert (lists, "OUTPUTS") in _imported_names(mods["ergosim/sweep/units.py"])
    writers = {("ergosim.experiment.csv_files", n) for n in ("write_allocations", "write_decisions",
                                                             "write_failures",
                                                             "write_ticks", "write_subjects",
                                                             "write_action_traces")}
    writers |= {("ergosim.experiment.subject_records", "write_records"),
                ("ergosim.experiment.kwear_state", "state_document")}
    users = {rel: sorted(f"{m}.{n}" for m, n in _imported_names(tree) & writers)
             for rel, tree in mods.items()}
    assert {rel: u for rel, u in users.items() if u and rel != "ergosim/experiment/outputs.py"} == {}
    assert users["ergosim/experiment/outputs.py"]  # the check reads the imports it means


def test_the_outputs_list_has_one_entry_per_name_and_file():
    from ergosim.experiment.outputs import OUTPUTS  # noqa: PLC0415

    names = [o.name for o in OUTPUTS]
    files = [f for o in OUTPUTS for f in o.files]
    assert len(set(names)) == len(names) and len(set(files)) == len(files)


# -- growth is visible -----------------------------------------------------------------------------------
def _lines(rel: str) -> int:
    return len((ROOT / rel).read_text(encoding="utf-8").splitlines())


def test_no_module_grows_past_the_limit():
    over = {rel: _lines(rel) for rel in _modules()
            if _lines(rel) > MODULE_LINES and rel not in MODULE_ALLOWANCES}
    assert over == {}, f"split these modules by concept (limit {MODULE_LINES} lines)"
    for rel, (cap, _why) in MODULE_ALLOWANCES.items():
        n = _lines(rel) if (ROOT / rel).is_file() else 0
        assert n <= cap, f"{rel} grew to {n} lines (its allowance is {cap})"
        assert n > MODULE_LINES, f"{rel} is {n} lines now: remove its allowance"


def test_no_function_grows_past_the_limit():
    limit = FUNCTION_LINES
    sizes: dict[tuple[str, str], int] = {}
    for rel, tree in _modules().items():
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                key = (rel, node.name)
                sizes[key] = max(sizes.get(key, 0), node.end_lineno - node.lineno + 1)
    over = {k: n for k, n in sizes.items() if n > limit and k not in FUNCTION_ALLOWANCES}
    assert over == {}, f"split these functions (limit {limit} lines)"
    for key, cap in FUNCTION_ALLOWANCES.items():
        assert sizes.get(key, 0) <= cap, f"{key} grew to {sizes[key]} lines (its allowance is {cap})"
        assert sizes.get(key, 0) > limit, f"{key} is {sizes.get(key, 0)} lines now: remove its allowance"
