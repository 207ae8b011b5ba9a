"""The MOTION block reader: numpy's reader over the whole block against the line-by-line reader, value for
value and bit for bit, and the same one-line error wherever a block is not well formed."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.errors import RecordingError
from ergosim.worker.bvh_motion import find_header, frame_lines, motion_header, read_frames
from ergosim.worker.bvh_parse import parse_bvh, parse_bvh_text

HEAD = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 3 Zrotation Xrotation Yrotation
  JOINT Chest
  {
    OFFSET 0 10 0
    CHANNELS 2 Xrotation Yrotation
    End Site
    {
      OFFSET 0 5 0
    }
  }
}
MOTION
Frames: {n}
Frame Time: 0.0166667
"""
N_CH = 5


def _line_by_line(text: str) -> np.ndarray:
    """The reference: every line split into strings, as the parser did before numpy read the block."""
    lines = text.splitlines()
    motion_at = next(k for k, line in enumerate(lines) if line.split()[:1] == ["MOTION"])
    n_frames, _, n = motion_header(lines, motion_at + 1, "<string>")
    return frame_lines(lines, n + 1, n_frames, N_CH, "<string>")


def _outcome(fn, text):
    try:
        return fn(text)
    except RecordingError as err:
        return str(err)


def _bits(x: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(x).view(np.uint64)


numbers = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, width=64).map(repr),
    st.floats(-1e3, 1e3).map(lambda x: f"{x:.6f}"),
    st.floats(-1e3, 1e3).map(lambda x: f"{x:.17e}"),
    st.integers(-10**20, 10**20).map(str),
    st.sampled_from(["-0", "0.000000", "-0.000000", "+3", ".5", "5.", "1e-320", "1E5", "-2.5e+02"]),
)
blanks = st.sampled_from([" ", "  ", "\t", " \t "])
endings = st.sampled_from(["\n", "\r\n", " \n", "\t\n", "\n\n", "\n \n"])


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.lists(numbers, min_size=N_CH, max_size=N_CH), blanks, endings), min_size=1,
                max_size=6))
def test_a_well_formed_block_is_read_at_once_with_the_bits_of_the_line_reader(rows):
    body = "".join(sep.join(vals) + end for vals, sep, end in rows)
    text = HEAD.replace("{n}", str(len(rows))) + body
    head = find_header(text)
    assert head is not None
    fast = read_frames(text[head[2]:], len(rows), N_CH)
    assert fast is not None
    assert np.array_equal(_bits(fast), _bits(_line_by_line(text)))
    data = text.encode()  # as parse_bvh reads a file: the bytes, read in place from the header's offset
    in_place = read_frames(data, len(rows), N_CH, find_header(data)[2])
    assert in_place is not None and np.array_equal(_bits(in_place), _bits(fast))
    assert np.array_equal(_bits(parse_bvh_text(text).motion), _bits(fast))


MUTATIONS = [
    ("1 2 3 4 5\n6 7 8 9 10\n", 2),
    ("1 2 3 4\n6 7 8 9 10\n", 2),  # a value missing
    ("1 2 3 4 5 6\n6 7 8 9 10\n", 2),  # one too many
    ("1 2 3 4 5\n6 7 8 9 10\n11 12 13 14 15\n", 2),  # a line too many
    ("1 2 3 4 5\n", 2),  # truncated
    ("1 2 3 4 nan\n6 7 8 9 10\n", 2),
    ("1 2 3 4 inf\n6 7 8 9 10\n", 2),
    ("1 2 3 4 1e999\n6 7 8 9 10\n", 2),
    ("1 2 3 4 abc\n6 7 8 9 10\n", 2),
    ("1 2 3 4 1_0\n6 7 8 9 10\n", 2),  # Python's float reads it, numpy's reader does not
    ("1 2\x0b3 4 5\n6 7 8 9 10\n", 2),  # a line break of str.splitlines numpy takes for a blank
    ("1 2 3 4 5\x0c6 7 8 9 10\n", 2),
    ("1 2 3 4 5\x1c\n6 7 8 9 10\n", 2),
    ("1 2 3 4 5\r6 7 8 9 10\r", 2),  # old Mac line ends
    ("1 2 3 4 5\n6 7 8 9 10\u00a0\n", 2),  # a non-ASCII blank
    ("1 2 3 4 5\n\u20026 7 8 9 10\n", 2),
    ("# a comment\n1 2 3 4 5\n6 7 8 9 10\n", 2),
    ("1,2,3,4,5\n6 7 8 9 10\n", 2),
    ("", 1),
    ("\n\n", 1),
]


@pytest.mark.parametrize("body,frames", MUTATIONS)
def test_every_block_gives_what_the_line_reader_gives(body, frames):
    text = HEAD.replace("{n}", str(frames)) + body
    expected = _outcome(_line_by_line, text)
    got = _outcome(lambda t: parse_bvh_text(t).motion, text)
    if isinstance(expected, str):
        assert got == expected
    else:
        assert np.array_equal(_bits(got), _bits(expected))


WELL_FORMED = [
    ("-0 0 -0.000000 1e-5 -1E-05\n1e300 -1.7976931348623157e308 5e-324 123456789012345678 0.1\n", 2),
    ("1\t2\t3\t4\t5\r\n6 \t7  8 9 10 \r\n", 2),  # tabs, runs of blanks, CRLF, trailing blanks
    ("  1 2 3 4 5   \n\n6 7 8 9 10", 2),  # leading blanks, a blank line, no final line end
    ("+3 .5 5. 1e-320 -2.5e+02\r\n", 1),
]


@pytest.mark.parametrize("body,frames", WELL_FORMED + MUTATIONS + [("1 2 3 4 5\n6 7 8", 2)])  # cut mid-frame
def test_a_file_read_in_place_gives_the_line_readers_values_or_error(tmp_path, body, frames):
    """parse_bvh reads a file's frame lines in place from its bytes: the line reader's values bit for bit,
    or its one-line error (a truncated last frame, a bad value, ...)."""
    text = HEAD.replace("{n}", str(frames)) + body
    path = tmp_path / "m.bvh"
    path.write_bytes(text.encode())
    expected = _outcome(_line_by_line, text)
    got = _outcome(lambda p: parse_bvh(p).motion, path)
    if isinstance(expected, str):
        assert got == expected.replace("<string>", str(path))
    else:
        assert np.array_equal(_bits(got), _bits(expected))
    if (body, frames) in WELL_FORMED:  # read at once, not by the line reader
        data = text.encode()
        assert read_frames(data, frames, N_CH, find_header(data)[2]) is not None


@pytest.mark.parametrize("body,frames", MUTATIONS[:6])
def test_a_file_read_as_bytes_gives_what_its_text_gives(tmp_path, body, frames):
    text = HEAD.replace("{n}", str(frames)) + body
    path = tmp_path / "m.bvh"
    path.write_bytes(text.encode())
    a = _outcome(lambda p: parse_bvh(p).motion, path)
    b = _outcome(lambda t: parse_bvh_text(t, str(path)).motion, text)
    assert type(a) is type(b)
    assert a == b if isinstance(a, str) else np.array_equal(_bits(a), _bits(b))


def test_the_header_is_found_past_a_long_hierarchy_and_the_prefix_cut():
    pad = "\r\n".join(" " * 70 for _ in range(3000))  # blank lines past the first 64 KiB prefix
    text = HEAD.replace("MOTION", pad + "\r\nMOTION").replace("{n}", "1") + "1 2 3 4 5\r\n"
    lines, motion_at, body_at = find_header(text)
    assert lines[motion_at].split() == ["MOTION"]
    assert text[body_at:] == "1 2 3 4 5\r\n"
    assert parse_bvh_text(text).motion.tolist() == [[1.0, 2.0, 3.0, 4.0, 5.0]]


def test_no_header_is_the_line_readers_error():
    text = HEAD.split("MOTION", maxsplit=1)[0] + "MOTION\nFrames: 2\n"
    assert find_header(text) is None
    with pytest.raises(RecordingError, match="file ends in MOTION, expected 'Frame Time:'"):
        parse_bvh_text(text)
