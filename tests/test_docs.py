"""The file-format reference cannot drift from the code: every key the readers accept is documented in
docs/workcell_format.md, every name docs/api.md uses exists, and the README's own-workcell walk-through
names files that exist.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from ergosim import api
from ergosim.experiment import scenario as scenariofile
from ergosim.experiment.protocol import PROTOCOL_KEYS
from ergosim.human.anthropometry import SEGMENT_SCALES
from ergosim.scenes import cell_schema
from ergosim.scenes.action_kinds import ACTION_KINDS
from ergosim.scenes.cellspec import SHAPES

ROOT = Path(__file__).resolve().parents[1]
BUNDLED_MODES = ("hrc", "rula", "h-only", "r-only")
FORMAT = (ROOT / "docs" / "workcell_format.md").read_text()

SCHEMAS = {
    "workcell top level": cell_schema.TopTable.model_fields,
    "workcell tables": dict.fromkeys(cell_schema.TABLES),
    "[worker]": cell_schema.WorkerTable.model_fields,
    "[robots.NAME]": cell_schema.RobotTable.model_fields,
    **{f"[furniture.NAME] type={t}": m.model_fields for t, m in cell_schema.FURNITURE.items()},
    "[parts.NAME]": cell_schema.PartTable.model_fields,
    "[[parts.NAME.slots]]": cell_schema.SlotTable.model_fields,
    "[targets.NAME]": cell_schema.TargetTable.model_fields,
    "[actions.LABEL]": cell_schema.ActionTable.model_fields,
    "[views.NAME]": cell_schema.ViewTable.model_fields,
    "[safety]": cell_schema.SafetyTable.model_fields,
    "scenario top level": dict.fromkeys(scenariofile._TOP),
    "[protocol]": dict.fromkeys(PROTOCOL_KEYS),
}


@pytest.mark.parametrize("table", sorted(SCHEMAS))
def test_every_key_of_the_files_is_documented(table):
    missing = [k for k in SCHEMAS[table] if f"`{k}`" not in FORMAT]
    assert not missing, f"docs/workcell_format.md lacks {table} keys {missing}"


def test_every_value_the_readers_name_is_documented():
    names = [*ACTION_KINDS, *SHAPES, *cell_schema.FURNITURE, *SEGMENT_SCALES, *BUNDLED_MODES, "fast", "paper"]
    missing = [n for n in names if f"`{n}`" not in FORMAT]
    assert not missing, missing


def test_the_api_guide_names_what_exists():
    guide = (ROOT / "docs" / "api.md").read_text()
    used = set(re.findall(r"api\.([A-Za-z_]+)", guide))
    assert used and used <= set(api.__all__), used - set(api.__all__)


def test_the_readme_walk_through_names_real_files():
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## Your own workcell"):]
    section = section[:section.index("\n## ", 1)]
    files = set(re.findall(r"examples/own_workcell/[\w.]+", section))
    assert {"examples/own_workcell/bracket.toml", "examples/own_workcell/bracket_task.toml",
            "examples/own_workcell/bracket_cell.toml"} <= files
    assert all((ROOT / f).is_file() for f in files)
    assert "ergosim run examples/own_workcell/bracket.toml" in section


# -- the README is a front page; history and measurements live elsewhere ------------------------------------
README_MAX_BYTES = 12 * 1024
"""The README's budget: a front page (STYLE.md: mink's is 3.6 KB), about 12 KB."""

QUICKSTART = (
    "python3 -m venv .venv && .venv/bin/pip install -q -e . && .venv/bin/ergosim run kwear-validation "
    "--rrd results/kwear-validation/run.rrd",
    "python3 -m venv .venv && .venv/bin/pip install -q -e '.[dev]' && .venv/bin/python -m pytest -q",
)
"""The two Quickstart commands, exactly: the hook and CI read them."""

ISSUE_NUMBERS_ALLOWED = ("docs/performance.md", "CHANGELOG.md")
_ISSUE = re.compile(r"\b[Ii]ssues? #?\d+|\bissue[- ]?#\d+|(?<![\w&/])#\d+\b")


def _docs() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def test_the_readme_is_a_front_page_with_the_two_quickstart_commands():
    readme = (ROOT / "README.md").read_bytes()
    assert len(readme) <= README_MAX_BYTES, f"README.md is {len(readme)} bytes (at most {README_MAX_BYTES})"
    text = readme.decode()
    quick = text[text.index("## Quickstart"):text.index("\n## ", text.index("## Quickstart") + 1)]
    assert [c for c in QUICKSTART if f"```bash\n{c}\n```" in quick] == list(QUICKSTART)
    for what in ("synthetic", "fidelity", "robot share", "takt", "docs/fidelity.md", "docs/performance.md"):
        assert what in text, what


def test_no_issue_numbers_outside_the_performance_page_and_the_changelog():
    found = {}
    for path in _docs():
        rel = path.relative_to(ROOT).as_posix()
        if rel in ISSUE_NUMBERS_ALLOWED:
            continue
        hits = _ISSUE.findall(re.sub(r"\(#[\w-]+\)", "", path.read_text(encoding="utf-8")))
        if hits:
            found[rel] = hits
    assert found == {}


def _anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
    heads = re.findall(r"(?m)^#+ (.*)$", text)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in heads}


def test_every_relative_link_of_the_docs_resolves():
    """Pages were split and moved: every relative link of the README, the docs and the changelog names a file
    that exists and, with a #fragment, a heading of that file."""
    bad = []
    for path in [*_docs(), ROOT / "CHANGELOG.md"]:
        text = re.sub(r"```.*?```", "", path.read_text(encoding="utf-8"), flags=re.S)
        for url in re.findall(r"\]\(([^)\s]+)\)", text):
            if url.startswith(("http://", "https://", "mailto:")):
                continue
            name, _, fragment = url.partition("#")
            target = path.parent / name if name else path
            if not target.exists():
                bad.append(f"{path.name}: {url} (no such file)")
            elif fragment and target.suffix == ".md" and fragment not in _anchors(target):
                bad.append(f"{path.name}: {url} (no such heading)")
    assert bad == []


def test_the_sweep_guide_lists_every_mode():
    """Every mode ergosim registers itself (asked in a fresh process: tests register modes of their own)."""
    ask = "from ergosim.twin.modes import MODES; print(*MODES.names())"
    names = subprocess.run([sys.executable, "-c", ask], capture_output=True, text=True, check=True,
                           timeout=120).stdout.split()
    row = next(line for line in (ROOT / "docs" / "sweeps.md").read_text().splitlines()
               if line.startswith("| `modes` |"))
    assert "kwear-lookahead" in names and [m for m in names if f"`{m}`" not in row] == []


def test_the_docs_point_to_no_path_outside_the_repository():
    for path in _docs():
        text = path.read_text(encoding="utf-8")
        assert "/work/" not in text and "shared/tools" not in text, path.name
