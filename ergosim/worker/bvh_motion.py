"""The MOTION block of a BVH file: its header, then every frame at once, or line by line to name a problem.

A well-formed block (``Frames:`` lines of one number per channel each, blank lines anywhere) is read in
one call of numpy's C text reader over the whole block (:func:`read_frames`). Anything else goes through
the line-by-line reader (:func:`frame_lines`), which names the first bad line; both give the same values
bit for bit (every number is converted by the same correctly rounded decimal-to-double conversion).
:func:`find_header` locates the block from a prefix of the file, so the frame lines are never split into
Python strings.
"""

from __future__ import annotations

import io
import warnings

import numpy as np

from ergosim.errors import RecordingError

__all__ = ["find_header", "header_value", "motion_header", "frame_lines", "read_frames"]

_PREFIX_CHARS = 1 << 16
# Line breaks of str.splitlines that numpy's reader takes for blanks: a block holding one is read by lines.
_OTHER_BREAKS = ("\x0b", "\x0c", "\x1c", "\x1d", "\x1e")


def _header_lines(lines: list[str]) -> tuple[int, int] | None:
    """(index of the MOTION line, index of the second non-empty line after it) in ``lines``, or None."""
    motion_at = next((k for k, line in enumerate(lines) if line.split()[:1] == ["MOTION"]), None)
    if motion_at is None:
        return None
    found = 0
    for k in range(motion_at + 1, len(lines)):
        if lines[k].strip():
            found += 1
            if found == 2:
                return motion_at, k
    return None


def find_header(text: str | bytes) -> tuple[list[str], int, int] | None:
    """The lines of ``text`` up to the one after ``Frames:`` (where ``Frame Time:`` belongs), the index of the
    MOTION line among them, and the offset in ``text`` where the frame lines start; None if ``text`` has no
    such header. ``text`` may be ASCII bytes. Only a growing prefix of ``text`` is split into lines."""
    size = _PREFIX_CHARS
    while True:
        whole = size >= len(text)
        prefix = text[:size]
        lines = (prefix.decode("ascii") if isinstance(prefix, bytes) else prefix).splitlines(keepends=True)
        if not whole and lines:
            lines.pop()  # it may continue past the prefix
        found = _header_lines(lines)
        if found is not None:
            motion_at, last = found
            return lines[:last + 1], motion_at, sum(map(len, lines[:last + 1]))
        if whole:
            return None
        size *= 4


def header_value(lines: list[str], n: int, label: str, source: str) -> tuple[str, int]:
    """The value after ``label`` (e.g. 'Frames:') on the next non-empty line at or after index ``n``."""
    while n < len(lines) and not lines[n].strip():
        n += 1
    if n >= len(lines):
        raise RecordingError(f"file ends in MOTION, expected '{label}'", where=f"{source}:{len(lines)}")
    text = " ".join(lines[n].split())  # tabs or runs of blanks anywhere, e.g. "Frame\tTime:\t0.0167"
    if not text.lower().startswith(label.lower()):
        raise RecordingError(f"expected '{label} <value>', found {text[:40]!r}", where=f"{source}:{n + 1}")
    return text[len(label):].strip(), n


def motion_header(lines: list[str], start: int, source: str) -> tuple[int, float, int]:
    """(frames, frame time [s], index of the Frame Time line) of the MOTION header after line ``start``."""
    value, n = header_value(lines, start, "Frames:", source)
    if not value.isdigit() or int(value) < 1:
        raise RecordingError(f"Frames must be a positive integer, found {value!r}", where=f"{source}:{n + 1}")
    n_frames = int(value)
    value, n = header_value(lines, n + 1, "Frame Time:", source)
    try:
        frame_time = float(value)
    except ValueError:
        frame_time = float("nan")
    if not (np.isfinite(frame_time) and frame_time > 0):
        raise RecordingError(f"Frame Time must be a positive number of seconds, found {value!r}",
                             where=f"{source}:{n + 1}")
    return n_frames, frame_time, n


def read_frames(text: str | bytes, n_frames: int, n_channels: int, start: int = 0) -> np.ndarray | None:
    """(n_frames, n_channels) frame values of the frame lines ``text[start:]`` (str, or ASCII bytes), read at
    once; None unless they are exactly that many lines of that many finite numbers (blank lines aside).
    Bytes are read in place: an hour of frames is 100 MB, which a slice would copy."""
    if n_channels < 1:
        return None
    if isinstance(text, bytes):
        if not (text.isascii() or text[start:].isascii()) or any(text.find(c.encode(), start) >= 0
                                                                for c in _OTHER_BREAKS):
            return None
        stream: io.IOBase = io.BytesIO(text)  # shares the bytes
        stream.seek(start)
    else:
        body = text[start:]
        if not body.isascii() or any(body.find(c) >= 0 for c in _OTHER_BREAKS):
            return None
        stream = io.StringIO(body)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an empty block warns; it is refused below
            motion = np.loadtxt(stream, dtype=float, comments=None, ndmin=2)
    except ValueError:
        return None
    if motion.shape != (n_frames, n_channels) or not np.isfinite(motion).all():
        return None
    return motion


def frame_lines(lines: list[str], start: int, n_frames: int, n_channels: int, source: str) -> np.ndarray:
    """(n_frames, n_channels) frame values of ``lines[start:]``, one line at a time: RecordingError naming the
    line of the first problem (a count, a value that is not a finite number, missing or extra lines)."""
    rows: list[list[str]] = []
    row_lines: list[int] = []
    for k in range(start, len(lines)):
        toks = lines[k].split()
        if not toks:
            continue
        if len(rows) == n_frames:
            raise RecordingError(f"more frame lines than Frames: {n_frames}", where=f"{source}:{k + 1}")
        if len(toks) != n_channels:
            raise RecordingError(f"frame {len(rows) + 1} has {len(toks)} values, expected {n_channels} "
                                 "(one per channel)", where=f"{source}:{k + 1}")
        rows.append(toks)
        row_lines.append(k + 1)
    if len(rows) < n_frames:
        raise RecordingError(f"file is truncated: Frames: {n_frames} but only {len(rows)} frame lines",
                             where=f"{source}:{len(lines)}")
    try:
        motion = np.array(rows, dtype=float).reshape(n_frames, n_channels)
        bad = ~np.isfinite(motion)
    except ValueError:
        bad = None
    if bad is None or bad.any():
        for toks, line in zip(rows, row_lines, strict=True):
            for col, tok in enumerate(toks):
                try:
                    ok = np.isfinite(float(tok))
                except ValueError:
                    ok = False
                if not ok:
                    raise RecordingError(f"value {tok!r} in column {col + 1} is not a finite number",
                                         where=f"{source}:{line}")
    return motion
