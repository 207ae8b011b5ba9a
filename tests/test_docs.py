"""The file-format reference cannot drift from the code: every key the readers accept is documented in
docs/workcell_format.md, every name docs/api.md uses exists, and the README's own-workcell walk-through
names files that exist.
"""

from __future__ import annotations

import re
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
