"""The built-in reader: CAM preambles, offsets, tools, G92, G53, G28/G30, refusals in one pass."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import ProgramError
from orthoglide_pin.program.offsets import make_setup
from orthoglide_pin.program.reader import check_refusals, read_moves

#: Rounding of coordinates read from text [m].
COORD_ATOL = 1e-12
MM = 1e-3

FANUC = """%
O1000
(T1 D=6 CR=0 - ZMIN=-5 - FLAT END MILL)
G90 G94 G17 G91.1
G21
G28 G91 Z0.
G90
T1 M6
S12000 M3
G54
M8
G0 X10 Y5
G43 Z15 H1
G0 Z5
G1 Z-1 F300
G17 G40 G49 G80 G90
G64 P0.01 Q0.01
G2 X20 Y5 I5 J0 F1000
M9
G28 G91 Z0
G90
M5
M30
%
"""


def _ends(read) -> list[list[float]]:
    return [list(np.round(m.end / MM, 9)) for m in read.moves]


def test_a_fanuc_style_program_is_read_as_written() -> None:
    setup = make_setup(origin=np.array([10.0, 20.0, -30.0]) * MM, tools={1: 50 * MM})
    read = check_refusals(read_moves(FANUC, setup))
    assert [m.kind for m in read.moves] == ["rapid"] * 2 + ["rapid"] * 3 + ["line", "arc"] + [
        "rapid"
    ] * 2
    ends = _ends(read)
    assert ends[:2] == [[0, 0, 0], [0, 0, 0]]  # G28 G91 Z0: home, where it is
    assert ends[2] == [20, 25, 0]  # G54 applied to X Y, Z kept
    assert ends[3] == [20, 25, 35]  # G43 H1: Z15 + G54's -30 + the tool's 50
    assert ends[4] == [20, 25, 25]
    assert ends[5] == [20, 25, 19]
    arc = read.moves[6]  # G49 cancelled the tool length: the arc keeps Z 19 mm
    np.testing.assert_allclose(arc.center / MM, [25, 25, 19], atol=1e-9)
    assert ends[6] == [30, 25, 19] and arc.turns == -1
    assert ends[8] == [30, 25, 0]  # G28 Z: home's Z
    assert read.tolerances[6] == pytest.approx(0.01 * MM)
    ignored = {i.word: (i.count, i.line) for i in read.ignored}
    assert ignored == {
        "O": (1, 2), "G94": (1, 4), "T": (1, 8), "M6": (1, 8), "S": (1, 9), "M3": (1, 9),
        "M8": (1, 11), "G40": (1, 16), "G64 Q": (1, 17), "M9": (1, 19), "M5": (1, 22),
    }  # fmt: skip
    assert read.lines == 23  # up to M30


def test_g10_g92_and_g53() -> None:
    text = (
        "G10 L2 P2 X1 Y2 Z3\nG55 G0 X0 Y0 Z0\nG92 X10\nG0 X11\nG92.2\nG0 X0\nG92.3\nG0 X10\n"
        "G92.1\nG53 G0 X7\nG10 L20 P0 X100\nG0 X100\nG0 X0\n"
    )
    read = check_refusals(read_moves(text))
    assert _ends(read) == [
        [1, 2, 3],  # G55 from G10 L2
        [2, 2, 3],  # G92 X10 made the current X 10: X11 is 1 mm on
        [1, 2, 3],  # G92.2 suspends it
        [1, 2, 3],  # G92.3 restores it: X10 is where G92 was set
        [7, 2, 3],  # G53: machine coordinates
        [7, 2, 3],  # G10 L20 made X100 the current point
        [-93, 2, 3],
    ]


def test_g28_g30_with_and_without_axes_and_given_points() -> None:
    setup = make_setup(offsets={5161: 1.0, 5162: 2.0, 5163: 3.0, 5181: -1.0})
    read = check_refusals(
        read_moves("G0 X5 Y5 Z5\nG28\nG0 X5\nG30 X6\nG28.1\nG0 X0\nG28\n", setup)
    )
    assert _ends(read) == [
        [5, 5, 5],
        [5, 5, 5],  # G28 without axes: LinuxCNC's waypoint where the tool is
        [1, 2, 3],  # G28: its reference point
        [5, 2, 3],
        [6, 2, 3],  # G30 X6: through X6, then G30's X
        [-1, 2, 3],
        [0, 2, 3],
        [0, 2, 3],
        [-1, 2, 3],  # G28.1 stored (-1, 2, 3)
    ]


def test_inches_incremental_and_machine_start() -> None:
    setup = make_setup(start=np.array([0.0, 0.0, 0.05]))
    read = check_refusals(read_moves("G20 G91 G1 X1 F10\nG21 X-25.4 Z-50\n", setup))
    np.testing.assert_allclose(read.moves[0].end, [0.0254, 0, 0.05], atol=COORD_ATOL)
    np.testing.assert_allclose(read.moves[1].end, [0, 0, 0], atol=COORD_ATOL)
    assert read.moves[0].feed == pytest.approx(10 * 0.0254 / 60)


def test_block_delete_is_honoured_on_request() -> None:
    text = "G0 X1\n/G0 X2\nG0 X3\n"
    assert len(read_moves(text).moves) == 3
    assert len(read_moves(text, make_setup(block_delete=True)).moves) == 2


def test_every_refusal_of_a_program_in_one_pass() -> None:
    text = (
        "G41 D1\nG1 X1 F100\nS100 M3\nG1 X#1\nG83 X1 Z-1 R1\nG43 H7 Z1\nM98 P100\nG10 L1 P1 Z3\n"
        "G1 X1 P3\n"
    )
    read = read_moves(text)
    assert [r.line for r in read.refusals] == [1, 4, 5, 6, 7, 8, 9]
    with pytest.raises(ProgramError) as info:
        check_refusals(read)
    message = str(info.value)
    assert message.startswith("program line 1: 7 refusals: cutter radius compensation G41")
    for words in ("line 4:", "NGC language", "needs Q > 0", "tool 7 is not in the tool table",
                  "M98", "G10 L1", "P3 with nothing"):  # fmt: skip
        assert words in message
    assert "\n" not in message


def test_program_end_stops_the_reading() -> None:
    read = read_moves("G0 X1\nM2\nG0 X2 (never read)\nthis is no G-code\n")
    assert len(read.moves) == 1 and read.lines == 2 and not read.refusals


def test_a_refused_move_does_not_refuse_the_next_lines() -> None:
    """Reading goes on from the refused move's programmed end."""
    read = read_moves("G0 X10\nG2 X0 Y10 I-10 J1 F100\nG2 X-10 Y0 I0 J-10\nG1 X1 F0\nG1 X2\n")
    assert [r.line for r in read.refusals] == [2, 4]
    np.testing.assert_allclose(read.moves[1].start / MM, [0, 10, 0], atol=1e-9)


@pytest.mark.parametrize(
    ("text", "line"),
    [
        ("G1 X1 F600\nG1 X2\n", 0),
        ("G1 X1 F600\nG64 P0.02\nG1 X2\nG61\n", 2),
        ("G61.1\nG1 X1 F600\n", 1),
        ("G1 X1 F600\nG1 X2 G61\nG64\n", 2),
    ],
)
def test_the_first_path_control_line_is_kept(text: str, line: int) -> None:
    read = read_moves(text)
    assert read.mode_line == line
    assert all(t is None for t in read.tolerances[: max(line - 1, 0)])  # exact stop before
