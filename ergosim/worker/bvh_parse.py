"""BVH (Biovision Hierarchy) files: the parser.

Supported subset: one ``ROOT``; ``JOINT`` and ``End Site`` to any depth; ``OFFSET x y z``; ``CHANNELS n``
with any mix and order of ``X/Y/Zposition`` and ``X/Y/Zrotation``; ``MOTION`` with ``Frames:`` and
``Frame Time:``, then one line of numbers per frame. Tokens may be spread over lines in any way inside
``HIERARCHY``. Joint names are single tokens. Rotation channels compose intrinsically in the listed order
(``Zrotation Xrotation Yrotation`` -> ``R = Rz @ Rx @ Ry``), the usual BVH reading: a vector in the joint's
frame maps to its parent's frame as ``v_parent = offset + R v_joint``.

Every problem raises :class:`~ergosim.errors.RecordingError` with ``where="<file>:<line>"``.
"""

from __future__ import annotations

import stat
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ergosim.errors import RecordingError
from ergosim.worker.bvh_motion import find_header, frame_lines, motion_header, read_frames

__all__ = ["BvhJoint", "BvhData", "parse_bvh", "parse_bvh_text", "MAX_BVH_BYTES"]

_AXIS = {"x": 0, "y": 1, "z": 2}
_CHANNEL_KINDS = ("position", "rotation")


@dataclass(frozen=True)
class BvhJoint:
    """One joint. ``offset`` [file units] is in the parent's frame; ``end_site``: End Site offset or None."""

    name: str
    parent: int  # index in BvhData.joints, -1 for the root
    offset: tuple[float, float, float]
    channels: tuple[str, ...]  # as written, e.g. ("Zrotation", "Xrotation", "Yrotation")
    first_channel: int  # column of channels[0] in BvhData.motion
    end_site: tuple[float, float, float] | None
    line: int

    @property
    def rotation_order(self) -> str:
        """Axes of the rotation channels in file order, e.g. ``"ZXY"``."""
        return "".join(c[0].upper() for c in self.channels if c[1:].lower() == "rotation")

    @property
    def rotation_columns(self) -> list[int]:
        return [self.first_channel + i for i, c in enumerate(self.channels) if c[1:].lower() == "rotation"]


@dataclass(frozen=True, eq=False)
class BvhData:
    """A parsed file: joints in depth-first order, ``motion`` (n_frames, n_channels), frame time [s]."""

    joints: tuple[BvhJoint, ...]
    frame_time: float
    motion: np.ndarray
    source: str

    @property
    def n_frames(self) -> int:
        return int(self.motion.shape[0])

    @property
    def rate_hz(self) -> float:
        """1 / frame time [Hz], snapped to a whole number within 0.02 % (files round the frame time)."""
        rate = 1.0 / self.frame_time
        return float(round(rate)) if abs(rate - round(rate)) <= 2e-4 * rate else rate

    def index(self, name: str) -> int:
        for i, j in enumerate(self.joints):
            if j.name == name:
                return i
        raise KeyError(name)

    def children(self, i: int) -> list[int]:
        return [k for k, j in enumerate(self.joints) if j.parent == i]


class _Tokens:
    """Whitespace tokens of the HIERARCHY lines, each with its 1-based line number."""

    def __init__(self, lines: list[str], source: str) -> None:
        self.items = [(tok, n + 1) for n, line in enumerate(lines) for tok in line.split()]
        self.pos = 0
        self.source = source
        self.last_line = max(len(lines), 1)

    def error(self, what: str, line: int | None = None) -> RecordingError:
        return RecordingError(what, where=f"{self.source}:{line or self.last_line}")

    def next(self, expected: str) -> tuple[str, int]:
        if self.pos >= len(self.items):
            raise self.error(f"file ends inside HIERARCHY, expected {expected}")
        self.pos += 1
        return self.items[self.pos - 1]

    def peek(self) -> str | None:
        return self.items[self.pos][0] if self.pos < len(self.items) else None

    def keyword(self, word: str) -> int:
        tok, line = self.next(f"'{word}'")
        if tok.upper() != word.upper():
            raise self.error(f"expected '{word}', found {tok!r}", line)
        return line

    def number(self, what: str) -> float:
        tok, line = self.next(what)
        try:
            x = float(tok)
        except ValueError:
            raise self.error(f"{what} must be a number, found {tok!r}", line) from None
        if not np.isfinite(x):
            raise self.error(f"{what} must be finite, found {tok!r}", line)
        return x

    def offset(self) -> tuple[float, float, float]:
        self.keyword("OFFSET")
        return (self.number("OFFSET x"), self.number("OFFSET y"), self.number("OFFSET z"))


def _parse_joint(tk: _Tokens, name: str, line: int, parent: int, joints: list[BvhJoint], n_ch: int) -> int:
    """Parse ``{ OFFSET .. CHANNELS .. children }`` of one joint; returns the channel count so far."""
    tk.keyword("{")
    offset = tk.offset()
    channels: tuple[str, ...] = ()
    if (tk.peek() or "").upper() == "CHANNELS":
        tk.next("CHANNELS")
        tok, cline = tk.next("the channel count")
        if not tok.isdigit():
            raise tk.error(f"CHANNELS count must be a non-negative integer, found {tok!r}", cline)
        names = []
        for _ in range(int(tok)):
            ch, chline = tk.next(f"{tok} channel names")
            if ch[:1].lower() not in _AXIS or ch[1:].lower() not in _CHANNEL_KINDS:
                raise tk.error(f"unknown channel {ch!r} of joint {name!r}; expected X/Y/Z followed by "
                               "'position' or 'rotation'", chline)
            names.append(ch)
        channels = tuple(names)
    me = len(joints)
    joints.append(BvhJoint(name, parent, offset, channels, n_ch, None, line))
    n_ch += len(channels)
    while True:
        tok, tline = tk.next("JOINT, End Site or '}'")
        if tok.upper() == "JOINT":
            child, cline = tk.next("a joint name")
            n_ch = _parse_joint(tk, child, cline, me, joints, n_ch)
        elif tok.upper() == "END":
            tk.keyword("Site")
            tk.keyword("{")
            site = tk.offset()
            tk.keyword("}")
            j = joints[me]
            joints[me] = BvhJoint(j.name, j.parent, j.offset, j.channels, j.first_channel, site, j.line)
        elif tok == "}":
            return n_ch
        else:
            raise tk.error(f"expected JOINT, End Site or '}}' in joint {name!r}, found {tok!r}", tline)


def parse_bvh_text(text: str, source: str = "<string>") -> BvhData:
    """Parse BVH ``text``; ``source`` names it in error messages."""
    return _parse(text, source)


def _split(text: str | bytes) -> list[str]:
    return (text.decode("ascii") if isinstance(text, bytes) else text).splitlines()


def _parse(text: str | bytes, source: str) -> BvhData:
    """Parse ``text``: a str, or the bytes of a file that is all ASCII (then numpy reads its frame lines
    straight from the bytes). Only the lines up to the MOTION header are split into strings, unless the
    frame lines are not well formed: then the whole text is, and the line-by-line reader names the problem."""
    head = find_header(text)
    if head is None:
        lines = _split(text)
        motion_at = next((k for k, line in enumerate(lines) if line.split()[:1] == ["MOTION"]), None)
    else:
        lines, motion_at, body_at = head
    tk = _Tokens(lines if motion_at is None else lines[:motion_at], source)
    tk.keyword("HIERARCHY")
    tk.keyword("ROOT")
    name, line = tk.next("the root joint's name")
    joints: list[BvhJoint] = []
    try:
        n_channels = _parse_joint(tk, name, line, -1, joints, 0)
    except RecursionError:  # joints nest by recursion; a skeleton is tens of levels deep, not hundreds
        raise RecordingError(f"the HIERARCHY nests joints more than {len(joints)} levels deep; not a "
                             "skeleton", where=source) from None
    if tk.peek() is not None:
        tok, line = tk.next("")
        what = "only one ROOT is supported" if tok.upper() == "ROOT" else f"unexpected {tok!r} after the root"
        raise tk.error(what, line)
    if motion_at is None:
        raise RecordingError("no MOTION section after the HIERARCHY", where=f"{source}:{len(lines)}")
    names = [j.name for j in joints]
    dup = next((k for k, n in enumerate(names) if n in names[:k]), None)
    if dup is not None:
        raise RecordingError(f"joint name {names[dup]!r} is used twice", where=f"{source}:{joints[dup].line}")
    motion = None
    if head is not None:
        n_frames, frame_time, n = motion_header(lines, motion_at + 1, source)
        motion = read_frames(text, n_frames, n_channels, body_at)
        if motion is None:
            lines = _split(text)
    if motion is None:
        n_frames, frame_time, n = motion_header(lines, motion_at + 1, source)
        motion = frame_lines(lines, n + 1, n_frames, n_channels, source)
    motion.setflags(write=False)
    return BvhData(tuple(joints), frame_time, motion, source)


MAX_BVH_BYTES = 256 << 20
"""Largest BVH file read [bytes]: about an hour of a full-body Xsens suit at 60 Hz (assumed ~100 channels of
8 characters per frame). Larger recordings: split them."""


def parse_bvh(path: str | Path) -> BvhData:
    """Read and parse the BVH file at ``path``: a regular file of at most :data:`MAX_BVH_BYTES` (a device such
    as /dev/zero or a named pipe is refused, never read)."""
    p = Path(path)
    try:
        st = p.stat()
        if stat.S_ISDIR(st.st_mode):
            raise RecordingError("is a directory, expected a BVH file", where=str(path))
        if not stat.S_ISREG(st.st_mode):
            raise RecordingError("not a regular file (a device or a pipe?); expected a BVH file",
                                 where=str(path))
        if st.st_size > MAX_BVH_BYTES:
            raise RecordingError(f"{st.st_size} bytes, more than the limit of {MAX_BVH_BYTES} "
                                 "(ergosim.worker.bvh_parse.MAX_BVH_BYTES)", where=str(path))
        with p.open("rb") as f:  # at most the limit, should the file grow meanwhile
            data = f.read(MAX_BVH_BYTES + 1)
        if len(data) > MAX_BVH_BYTES:
            raise RecordingError(f"more than the limit of {MAX_BVH_BYTES} bytes", where=str(path))
        text = data if data.isascii() else data.decode("utf-8-sig")
    except FileNotFoundError:
        raise RecordingError("no such file", where=str(path)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise RecordingError(f"cannot read BVH file: {exc}", where=str(path)) from None
    return _parse(text, str(path))
