"""Imported first by the scripts that run a benchmark or a study: puts the repository's root on
``sys.path``, so ``benchmarks/`` (beside ``ergosim/``, not installed with it) imports from a script run as
``python scripts/NAME.py``."""

import sys
from pathlib import Path

ROOT = str(Path(__file__).resolve().parents[1])
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)
