"""The sweep's tidy table: one row per design, its parameters and its metrics.

:func:`table_columns` gives the column order (the key, status, error and mode,
the parameters, the swept axes, the metrics, and a program's columns when the
sweep has one); :func:`sweep_table` assembles the rows of
:func:`~orthoglide_pin.sweep.metrics.evaluate_design` into a pandas DataFrame
of those columns and types.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

from orthoglide_pin._lazy import optional_import
from orthoglide_pin._validation import flag, mappings, name_list
from orthoglide_pin.sweep import accuracy as _accuracy
from orthoglide_pin.sweep import program as _program
from orthoglide_pin.sweep.spec import HEAD_COLUMNS, METRIC_COLUMNS, PARAMETER_COLUMNS

if TYPE_CHECKING:
    import pandas as pd


def table_columns(names: Sequence[str], program: bool = False, cut: bool = False) -> list[str]:
    """Column order of the table for axes ``names`` (and a ``program``'s and a ``cut``'s)."""
    extra = [n for n in names if n not in PARAMETER_COLUMNS]
    return [
        *HEAD_COLUMNS,
        *PARAMETER_COLUMNS,
        *extra,
        *METRIC_COLUMNS,
        *_program.columns(program),
        *_accuracy.columns(program and cut),
    ]


def sweep_table(
    rows: Iterable[Mapping[str, Any]],
    names: Sequence[str],
    program: bool = False,
    cut: bool = False,
) -> pd.DataFrame:
    """The tidy table: one row per design, its parameters and its metrics.

    Args:
        rows: Rows of :func:`~orthoglide_pin.sweep.metrics.evaluate_design`,
            in the order of the table.
        names: Names of the swept axes.
        program: Whether the sweep has a program (its columns).
        cut: Whether it has a cut file too (its columns).

    Returns:
        A DataFrame with the columns of :func:`table_columns`: text columns
        ``key, status, error, mode``, ``bounds_hold`` as a nullable boolean,
        every other column as float (NaN where a design is invalid).

    Raises:
        MissingExtraError: pandas is not installed (``orthoglide-pin[tables]``).
    """
    pd = optional_import("pandas", "tables", "a sweep's table")
    rows, names = mappings("rows", rows, "rows of evaluate_design"), name_list("names", names)
    columns = table_columns(names, flag("program", program), flag("cut", cut))
    frame = pd.DataFrame([{c: r.get(c) for c in columns} for r in rows], columns=columns)
    for c in columns:
        if c in HEAD_COLUMNS or c in _program.PROGRAM_TEXT_COLUMNS:
            frame[c] = frame[c].fillna("").astype(str)
        elif c == "bounds_hold":
            frame[c] = frame[c].astype("boolean")
        else:
            frame[c] = pd.to_numeric(frame[c], errors="coerce").astype("float64")
    return frame


__all__ = ["sweep_table", "table_columns"]
