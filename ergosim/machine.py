"""What this machine can hold: its physical memory, which bounds the values a run, a sweep or a planner
accepts (a value that would need more is refused with one line before anything starts)."""

from __future__ import annotations

import os

__all__ = ["physical_memory"]

_FALLBACK = 16 * 1024**3
"""Bytes assumed where the platform does not say (16 GiB)."""


def physical_memory() -> int:
    """This machine's physical memory [bytes]."""
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return _FALLBACK
