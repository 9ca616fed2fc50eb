"""Line numbers of a program's offsets: counted on the buffer in place, an mmap as much as
bytes, they are the line ends before the offset plus one."""
from __future__ import annotations

import mmap

from hypothesis import given, settings
from hypothesis import strategies as st

from ncverify.source import ProgramSource

_TEXT = st.lists(st.sampled_from([b"G1 X1.\n", b"\n", b"M30", b"(a\r\nb)\n", b"N10 G0 Z5.\r\n", b"x" * 300]), max_size=40).map(b"".join)


@settings(max_examples=200, deadline=None)
@given(text=_TEXT, cut=st.floats(0, 1))
def test_a_line_number_counts_the_line_ends_before_its_offset(text, cut):
    offset = int(len(text) * cut)
    assert ProgramSource.from_bytes(text, "t.nc").line_number_at(offset) == text[:offset].count(b"\n") + 1


def test_line_numbers_in_a_long_mapped_file(tmp_path):
    """Counted in pieces across a file of a few MiB, from wherever a number is known."""
    lines = [f"G1 X{index}. Y{index % 7}.\n".encode() for index in range(300_000)]
    path = tmp_path / "long.nc"
    path.write_bytes(b"".join(lines))
    source = ProgramSource.open(path)
    assert isinstance(source.buffer, mmap.mmap)
    ends = [0]
    for line in lines:
        ends.append(ends[-1] + len(line))
    for index in (299_999, 1, 150_000, 200_001, 0):
        assert source.line_number_at(ends[index]) == index + 1
    assert source.line_number_at(len(source)) == len(lines) + 1
