"""A sampled plan written to disk a chunk at a time, and the light copy its page plots.

:func:`write_trajectory` writes the chunks of
:func:`~orthoglide_pin.planning.sampling.sample_chunks` to one file as they
come, so that the memory it needs does not grow with the program's length:

* ``csv``: a first line (the design comment), the header, then one row per
  sample (10 significant digits), as :func:`~orthoglide_pin.planning.sampling.csv_text`;
* ``parquet``: the same columns (float64) in row groups of one chunk each, the
  first line kept in the file's metadata under ``orthoglide``; it needs
  pyarrow (the ``[tables]`` extra), is about 40 % smaller and twice as fast to write.

Meanwhile it keeps a **plotting copy** of at most about :data:`PLOT_SAMPLES`
rows per plotted column: the samples are cut into buckets, and of each bucket
it keeps the first row and the rows of the smallest and largest value of each
plotted column (:data:`ENVELOPE`). Every peak of those columns is kept
exactly, so the page's peaks and curves' envelopes are those of the full file.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.planning.sampling import COLUMNS

FloatArray = NDArray[np.float64]

#: The formats of the trajectory file.
FORMATS: Final = ("csv", "parquet")
#: Buckets of the plotting copy [-].
PLOT_SAMPLES: Final[int] = 4000
#: The columns whose extremes every bucket of the plotting copy keeps.
ENVELOPE: Final = (
    "path_speed", "qd1", "qd2", "qd3", "tau1", "tau2", "tau3", "F1", "F2", "F3",
)  # fmt: skip


@dataclass(frozen=True)
class Written:
    """What :func:`write_trajectory` wrote.

    Attributes:
        samples: Rows written [-].
        plot: The plotting copy: column name -> values (see the module).
    """

    samples: int
    plot: dict[str, FloatArray]


def envelope(
    columns: dict[str, FloatArray], bucket: int, extremes: tuple[str, ...] = ENVELOPE
) -> dict[str, FloatArray]:
    """Of every ``bucket`` rows, the first and those of each ``extremes`` column's extremes."""
    n = columns["t"].size
    if bucket <= 1 or n <= 2:
        return dict(columns)
    starts = np.arange(0, n, bucket)
    keep = [starts, np.array([n - 1])]
    cut = starts.size * bucket - n  # pad the last bucket with its own last value
    for name in extremes:
        if name not in columns:
            continue
        padded = np.concatenate([columns[name], np.full(cut, columns[name][-1])])
        table = padded.reshape(-1, bucket)
        for pick in (np.argmin(table, axis=1), np.argmax(table, axis=1)):
            keep.append(np.minimum(starts + pick, n - 1))
    rows = np.unique(np.concatenate(keep))
    return {name: values[rows] for name, values in columns.items()}


def write_trajectory(
    path: str | os.PathLike[str],
    chunks: Iterable[dict[str, FloatArray]],
    total: int,
    *,
    first_line: str = "",
    file_format: str = "csv",
    order: tuple[str, ...] = COLUMNS,
    extremes: tuple[str, ...] = ENVELOPE,
) -> Written:
    """Write the chunks to ``path`` as they come (see the module).

    Args:
        path: The file.
        chunks: Column name -> values, for consecutive samples.
        total: The number of samples the chunks hold (sizes the plotting buckets).
        first_line: A line written first (CSV), or kept in the metadata
            (Parquet), newline included.
        file_format: ``"csv"`` or ``"parquet"``.
        order: The columns to write, in this order; those absent are left out.
        extremes: The columns whose extremes the plotting copy keeps (:data:`ENVELOPE`).

    Returns:
        The rows written and the plotting copy.

    Raises:
        InvalidParameterError: An unknown format.
        MissingExtraError: Parquet without pyarrow (``[tables]``).
    """
    if file_format not in FORMATS:
        raise InvalidParameterError("file_format", file_format, " or ".join(FORMATS))
    bucket = max(1, -(-int(total) // PLOT_SAMPLES))
    plots: list[dict[str, FloatArray]] = []
    count = 0
    writer: Any = None
    with open(path, "w" if file_format == "csv" else "wb") as handle:
        try:
            for columns in chunks:
                names = [c for c in order if c in columns]
                if file_format == "csv":
                    if count == 0:
                        handle.write(first_line + ",".join(names) + "\n")
                    handle.write(_csv_rows([columns[c] for c in names]))
                else:
                    writer = _parquet_chunk(writer, handle, columns, names, first_line)
                count += columns["t"].size
                plots.append(envelope(columns, bucket, extremes))
        finally:
            if writer is not None:
                writer.close()
    plot = {name: np.concatenate([p[name] for p in plots]) for name in plots[0]}
    return Written(count, plot)


def _csv_rows(columns: list[FloatArray]) -> str:
    """The rows of the columns as CSV (10 significant digits), as ``numpy.savetxt`` writes them.

    One format string for the whole chunk: a third faster than a row at a time.
    """
    if not columns or columns[0].size == 0:
        return ""
    row = ",".join(["%.10g"] * len(columns)) + "\n"
    values = np.column_stack(columns).ravel().tolist()
    return (row * columns[0].size) % tuple(values)


def _parquet_chunk(
    writer: Any, handle: Any, columns: dict[str, FloatArray], names: list[str], first_line: str
) -> Any:
    """Append one row group (opening the writer on the first)."""
    from orthoglide_pin._lazy import optional_import

    pa = optional_import("pyarrow", "tables", "a Parquet trajectory")
    pq = optional_import("pyarrow.parquet", "tables", "a Parquet trajectory")
    table = pa.table({c: columns[c] for c in names})
    if writer is None:
        meta = {"orthoglide": first_line.rstrip("\n")}
        table = table.replace_schema_metadata(meta)
        writer = pq.ParquetWriter(handle, table.schema)
    writer.write_table(table.replace_schema_metadata(writer.schema.metadata))
    return writer
