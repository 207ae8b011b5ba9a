"""One schema layer for every file format (workcell, task, sweep, scenario), on pydantic v2.

:mod:`ergosim.schema.values` holds the value kinds (a finite number, ``n`` numbers, names, an axis, ...):
how a TOML value is checked and how a ``--set`` string becomes one. :mod:`ergosim.schema.document` holds
the tables (pydantic models whose fields are kinds), the check of a table that turns pydantic's errors into
one line naming the file and the entry, and the one dotted-path override of every format.
"""

from ergosim.schema.document import Keyed, Listed, Named, Table, Tree, check_table, override, paths, table
from ergosim.schema.values import Invalid, Kind, finite_float, kind_of

__all__ = ["Table", "table", "Tree", "Named", "Listed", "Keyed", "check_table", "override", "paths",
           "Kind", "Invalid", "kind_of", "finite_float"]
