"""Measurement files: what is read, what is refused, the hash."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.calibration.measurements import MAX_BYTES, parse_measurements

HEADER = "q1,q2,q3,x,y,z"


def _rows(n: int, seed: int = 0) -> str:
    values = np.random.default_rng(seed).uniform(-0.05, 0.05, (n, 6))
    return "".join(",".join(repr(float(v)) for v in row) + "\n" for row in values)


def test_columns_in_any_order_extra_columns_comments() -> None:
    text = "# tracker run 3\nz,y,x,note,q3,q2,q1\n" + "".join(
        f"{i * 1e-3},{2e-3},{3e-3},pose{i},{-i * 1e-3},{i * 2e-3},{i * 3e-3}\n\n"
        for i in range(12)
    )
    data = parse_measurements(text.encode(), "m.csv")
    assert len(data) == 12
    np.testing.assert_array_equal(data.q[5], [15e-3, 10e-3, -5e-3])
    np.testing.assert_array_equal(data.points[5], [3e-3, 2e-3, 5e-3])
    assert data.sha256 == hashlib.sha256(text.encode()).hexdigest()


def test_a_byte_order_mark_is_allowed() -> None:
    text = HEADER + "\n" + _rows(12)
    with_bom = parse_measurements(b"\xef\xbb\xbf" + text.encode())
    np.testing.assert_array_equal(with_bom.q, parse_measurements(text.encode()).q)


@pytest.mark.parametrize(
    ("data", "words"),
    [
        (b"", "empty"),
        (b"\xff\xfe", "not UTF-8"),
        ((HEADER + "\n1,2\n").encode(), "row 0 has 2 fields"),
        ((HEADER + "\n" + _rows(12) + "0,0,0,0,0,inf\n").encode(), "row 12, column z: inf"),
        ((HEADER + "\n" + _rows(12) + "0,0,0,0,0,120.5\n").encode(), "millimetres"),
    ],
)
def test_refusals_are_one_line(data: bytes, words: str) -> None:
    with pytest.raises(og.CalibrationError, match=None) as info:
        parse_measurements(data, "m.csv")
    assert words in str(info.value) and "\n" not in str(info.value)


def test_files_are_read_safely(tmp_path: Path) -> None:
    good = tmp_path / "m.csv"
    good.write_text(HEADER + "\n" + _rows(15))
    assert len(og.read_measurements(good)) == 15
    with pytest.raises(og.InvalidParameterError, match="directory"):
        og.read_measurements(tmp_path)
    big = tmp_path / "big.csv"
    with open(big, "wb") as fh:
        fh.truncate(MAX_BYTES + 10)  # sparse: costs nothing
    with pytest.raises(og.InvalidParameterError, match="at most"):
        og.read_measurements(big)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises((og.CalibrationError, og.InvalidParameterError)):
        og.read_measurements(fifo)  # no writer: not waited for, and empty is refused
