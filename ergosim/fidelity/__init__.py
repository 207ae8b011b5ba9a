"""The twin against its paper: run §7.1 and §7.2, compare row by row, report (``ergosim fidelity``)."""

from ergosim.fidelity.checks import FULL_BOUNDS, QUICK_BOUNDS, Bounds, Row, fidelity_rows
from ergosim.fidelity.experiments import FULL, QUICK, Plan, Runs, run_experiments
from ergosim.fidelity.report import fidelity_document, report_text, write_report

__all__ = ["Bounds", "Row", "FULL_BOUNDS", "QUICK_BOUNDS", "fidelity_rows", "Plan", "Runs", "FULL", "QUICK",
           "run_experiments", "fidelity_document", "report_text", "write_report"]
