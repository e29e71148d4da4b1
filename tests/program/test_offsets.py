"""Offsets and tool-table files in LinuxCNC's formats, and the set-up they make."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.program.offsets import make_setup, read_offsets, read_tool_table

MM = 1e-3


def test_a_parameter_file_sets_g54_to_g59_3_and_the_reference_points(tmp_path) -> None:
    path = tmp_path / "offsets.var"
    path.write_text(
        "5161 1.5\n5163 -2\n5181 4 ; G30 X\n5221 10\n5222 20\n5223 -30\n5241 7\n"
        "5381 9\n5220 1.000000  # the active system, read and unused\n\n"
    )
    setup = make_setup(offsets=read_offsets(path))
    np.testing.assert_allclose(setup.g28, [1.5 * MM, 0, -2 * MM])
    np.testing.assert_allclose(setup.g30, [4 * MM, 0, 0])
    np.testing.assert_allclose(setup.work_offsets[0], [10 * MM, 20 * MM, -30 * MM])
    assert setup.work_offsets[1, 0] == pytest.approx(7 * MM)  # G55
    assert setup.work_offsets[8, 0] == pytest.approx(9 * MM)  # G59.3
    moved = make_setup(offsets=read_offsets(path), origin=(0.0, 0.0, 0.001))
    np.testing.assert_allclose(moved.work_offsets[0], [0, 0, 0.001])  # --origin wins


def test_a_tool_table(tmp_path) -> None:
    path = tmp_path / "tool.tbl"
    path.write_text("T1 P1 Z50.0 D6 ;6 mm end mill\nT2 P2 D3\n\n;T9 Z1\nT12 P5 X1 Z-0.5\n")
    assert read_tool_table(path) == {1: pytest.approx(0.05), 2: 0.0, 12: pytest.approx(-0.0005)}


@pytest.mark.parametrize(
    ("reader", "text", "words"),
    [
        (read_offsets, "5221\n", "NUMBER VALUE"),
        (read_offsets, "5221 nan\n", "finite"),
        (read_offsets, "G54 1\n", "NUMBER VALUE"),
        (read_tool_table, "P1 Z5\n", "tool number"),
        (read_tool_table, "T1 Z5\nT1 Z6\n", "each tool once"),
        (read_tool_table, "T1 Zfoo\n", "finite"),
        (read_tool_table, "T1.5 Z1\n", "tool number"),
    ],
)
def test_bad_files_name_their_line(tmp_path, reader, text: str, words: str) -> None:
    path = tmp_path / "f.txt"
    path.write_text(text)
    with pytest.raises(InvalidParameterError, match=words) as info:
        reader(path)
    assert "f.txt" in str(info.value)


@pytest.mark.parametrize("reader", [read_offsets, read_tool_table])
def test_a_file_of_another_kind_shows_at_most_one_word(tmp_path, reader) -> None:
    """A password file given as a tool table: its first word at most, nothing after it."""
    path = tmp_path / "passwd"
    path.write_text(
        "rootSECRET:x:0:0:root:/root:/bin/bash\nuser:x:1000:1000::/home/user:/bin/sh\n"
    )
    with pytest.raises(InvalidParameterError) as info:
        reader(path)
    message = str(info.value)
    assert ":x:0" not in message and "/bin/bash" not in message and "user" not in message
    assert "line 1" in message
