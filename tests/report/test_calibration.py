"""The calibration's page: the outliers counted, then listed by row."""

from __future__ import annotations

from orthoglide_pin.report.calibration import CSV_NAME, outliers_text


def test_the_outliers_are_counted_before_their_rows_are_listed() -> None:
    assert outliers_text((), 60) == "none of 60 poses"
    assert outliers_text((5,), 60) == f"1 of 60 poses: row 5 ({CSV_NAME}'s row column, from 0)"
    two = outliers_text((3, 41), 60)
    assert two.startswith("2 of 60 poses: rows 3, 41 (")
