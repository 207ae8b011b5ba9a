"""Shared test set-up: offscreen rendering on a machine without a display (read when mujoco is imported)."""

from ergosim.cli import headless_gl

headless_gl()
