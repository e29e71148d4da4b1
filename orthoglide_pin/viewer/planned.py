"""A planned trajectory read back for the viewer: ``trajectory.csv`` of ``orthoglide plan``.

:func:`read_trajectory` reads the file that ``orthoglide plan --out DIR``
writes (:data:`~orthoglide_pin.planning.sampling.COLUMNS`, SI units), or the
``simulation.csv`` of ``orthoglide simulate`` (the simulated tool), and checks
it before anything is drawn, each problem one line naming the file and, where
it applies, the row (1 for the first data row) and the column:

* a header of known, distinct column names, with at least
  :data:`REQUIRED_COLUMNS` (``t, x, y, z, path_speed``);
* every row with as many fields as the header, every value a finite number;
* at least two rows, the times strictly increasing, the path speeds ``>= 0``;
* a first line ``# orthoglide design: DIGEST, leg_length: L`` naming the
  machine's design (:func:`~orthoglide_pin.machine.digest.design_digest`):
  another design's file is refused, naming both
  (:class:`~orthoglide_pin.exceptions.DesignMismatchError`), and so is a file
  that records none (written before designs were recorded: the message gives
  the line to add);
* every tool point inside the machine's cube (within :data:`CUBE_TOL` [m],
  as the planner accepts), since a plan of another machine is not this one's.

A file named ``*.parquet`` (``--trajectory-format parquet``, the ``[tables]``
extra: pyarrow) is read as Parquet, with the same checks: its size is checked
before it is read (at most :data:`MAX_TRAJECTORY_BYTES`), its column names are
those of the CSV header, the CSV's first line is kept in its metadata under
:data:`METADATA_KEY`, and its rows are at most :data:`MAX_PARQUET_ROWS`
(counted before any is decoded, since a small file may hold many). Of its
columns only :data:`REQUIRED_COLUMNS` are decoded, whatever else it holds.

:func:`feed_colors` gives the colours of the path by feed (the path speed) on
a colormap, and :func:`feed_legend` the swatches that name them, in mm/min as
on every page and terminal summary (:mod:`~orthoglide_pin.report.units`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._io import read_input_bytes, read_input_text
from orthoglide_pin._lazy import optional_import
from orthoglide_pin.exceptions import InvalidParameterError, short_repr
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.cube import Cube
from orthoglide_pin.machine.digest import CSV_DESIGN_PREFIX, check_design, read_design_comment
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.report.units import quantity

FloatArray = NDArray[np.float64]

#: Columns the viewer needs.
REQUIRED_COLUMNS: Final = ("t", "x", "y", "z", "path_speed")
#: The columns of a simulated run (``orthoglide simulate``'s ``simulation.csv``) beyond a plan's.
SIMULATION_COLUMNS: Final = (
    "x_ref", "y_ref", "z_ref", "q1_ref", "q2_ref", "q3_ref", "e1", "e2", "e3",
    "tau_available1", "tau_available2", "tau_available3",
    "saturated1", "saturated2", "saturated3", "contour_error", "line", "rapid",
    "cutting",
)  # fmt: skip
#: Every column a planned trajectory (``orthoglide plan``'s) or a simulated run may have.
KNOWN_COLUMNS: Final = (
    "t", "x", "y", "z", "path_speed", "q1", "q2", "q3", "qd1", "qd2", "qd3",
    "qdd1", "qdd2", "qdd3", "F1", "F2", "F3", "tau1", "tau2", "tau3", *SIMULATION_COLUMNS,
)  # fmt: skip
#: A point this far outside the cube is still inside [m], as for the planner.
CUBE_TOL: Final[float] = 1e-9
#: Largest file read [bytes] (a million rows of every column).
MAX_TRAJECTORY_BYTES: Final[int] = 512_000_000
#: Most rows of a Parquet trajectory read [-] (its five columns: 400 MB of float64).
MAX_PARQUET_ROWS: Final[int] = 10_000_000
#: Colormap of the feed, and how many swatches name it.
FEED_COLORMAP: Final = "viridis"
FEED_SWATCHES: Final[int] = 5
#: A file named so is read as Parquet (``--trajectory-format parquet``).
PARQUET_SUFFIX: Final = ".parquet"
#: The key of a Parquet file's metadata that holds the CSV's first line.
METADATA_KEY: Final = "orthoglide"


@dataclass(frozen=True)
class PlannedTrajectory:
    """A planned trajectory as the viewer plays it.

    Attributes:
        t: Times [s], (N,), strictly increasing.
        p: Tool points [m], (N, 3).
        path_speed: The tool's path speed (the feed) [m/s], (N,).
    """

    t: FloatArray
    p: FloatArray
    path_speed: FloatArray


def _bad(path: str, where: str, allowed: str) -> InvalidParameterError:
    """``invalid trajectory file=PATH: expected ALLOWED (WHERE)``, the path shown whole."""
    return InvalidParameterError("trajectory file", Path(path), f"{allowed} ({where})")


def _rows(path: str, lines: list[str], width: int) -> FloatArray:
    """The data rows as numbers (one error naming the first bad row)."""
    try:
        data = np.loadtxt(lines, delimiter=",", ndmin=2, dtype=np.float64)
        if data.shape[1] == width:
            return np.asarray(data)
    except ValueError:
        pass
    for k, line in enumerate(lines, 1):
        fields = line.split(",")
        if len(fields) != width:
            raise _bad(path, f"row {k}", f"{width} comma-separated fields, as the header")
        for field in fields:
            try:
                float(field)
            except ValueError:
                raise _bad(path, f"row {k}: {short_repr(field.strip())}", "numbers") from None
    raise _bad(path, "rows", "numeric rows of the header's width")  # pragma: no cover


def _csv_columns(name: str) -> tuple[tuple[str, float | None] | None, dict[str, FloatArray]]:
    """The recorded design and the :data:`REQUIRED_COLUMNS` of a CSV file, checked."""
    text = read_input_text(name, "trajectory file", MAX_TRAJECTORY_BYTES)
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        raise _bad(name, "empty", "a header t,x,y,z,path_speed,... and rows")
    try:
        recorded = read_design_comment(lines[0], "design")
    except InvalidParameterError:
        allowed = f"a first line '{CSV_DESIGN_PREFIX} DIGEST, leg_length: L' (og.design_digest)"
        raise _bad(name, "first line", allowed) from None
    lines = [line for line in lines if not line.lstrip().startswith("#")]
    if not lines:
        raise _bad(name, "empty", "a header t,x,y,z,path_speed,... and rows")
    header = [c.strip() for c in lines[0].split(",")]
    _check_header(name, header)
    rows = _rows(name, lines[1:], len(header))
    if rows.shape[0] < 2:
        raise _bad(name, f"{rows.shape[0]} rows", "at least 2 rows")
    bad = ~np.isfinite(rows)
    if bad.any():
        k, j = np.argwhere(bad)[0]
        raise _bad(name, f"row {k + 1}, {header[j]} = {rows[k, j]}", "finite numbers")
    return recorded, {c: rows[:, header.index(c)] for c in REQUIRED_COLUMNS}


def _check_header(name: str, header: list[str]) -> None:
    """Known, distinct column names, with at least :data:`REQUIRED_COLUMNS`."""
    for c in header:
        if c not in KNOWN_COLUMNS:
            raise _bad(name, f"column {short_repr(c)}", "columns of " + ",".join(KNOWN_COLUMNS))
        if header.count(c) > 1:
            raise _bad(name, f"column {short_repr(c)} twice", "each column once")
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise _bad(name, "no " + ", ".join(missing), "the columns " + ",".join(REQUIRED_COLUMNS))


_WRITTEN_BY = "a Parquet file (orthoglide plan or simulate --trajectory-format parquet)"


def _design(name: str, metadata: dict[bytes, bytes] | None) -> tuple[str, float | None] | None:
    """The design the metadata records (``None`` if none), as the CSV's first line."""
    raw = (metadata or {}).get(METADATA_KEY.encode())
    if raw is None:
        return None
    allowed = f"metadata '{METADATA_KEY}': '{CSV_DESIGN_PREFIX} DIGEST, leg_length: L'"
    try:
        recorded = read_design_comment(raw.decode("utf-8"), "design")
    except (UnicodeDecodeError, InvalidParameterError):
        raise _bad(name, f"metadata '{METADATA_KEY}'", allowed) from None
    if recorded is None:
        raise _bad(name, f"metadata '{METADATA_KEY}'", allowed)
    return recorded


def _parquet_columns(name: str) -> tuple[tuple[str, float | None] | None, dict[str, FloatArray]]:
    """The recorded design and the :data:`REQUIRED_COLUMNS` of a Parquet file, checked.

    Args:
        name: The file, as the user gave it (named in every error).

    Returns:
        ``(digest, leg length [m])`` or ``None`` when it records no design, and
        column name -> values (float64, finite, at least two rows).

    Raises:
        MissingExtraError: pyarrow is missing (the ``[tables]`` extra).
        InvalidParameterError: One line naming the file and what is wrong.
    """
    pa: Any = optional_import("pyarrow", "tables", "a Parquet trajectory")
    pq: Any = optional_import("pyarrow.parquet", "tables", "a Parquet trajectory")
    data = read_input_bytes(name, "trajectory file", MAX_TRAJECTORY_BYTES)
    try:
        source = pq.ParquetFile(pa.BufferReader(data))
        schema = source.schema_arrow
        rows = int(source.metadata.num_rows)
    except (pa.ArrowException, OSError, ValueError):
        raise _bad(name, "not a Parquet file", _WRITTEN_BY) from None
    _check_header(name, list(schema.names))
    recorded = _design(name, schema.metadata)
    for c in REQUIRED_COLUMNS:
        kind = schema.field(c).type
        if not (pa.types.is_floating(kind) or pa.types.is_integer(kind)):
            raise _bad(name, f"column {c} of type {kind}", "numeric columns (float64)")
    if rows < 2:
        raise _bad(name, f"{rows} rows", "at least 2 rows")
    if rows > MAX_PARQUET_ROWS:
        raise _bad(name, f"{rows} rows", f"at most {MAX_PARQUET_ROWS} rows")
    try:
        table = source.read(columns=list(REQUIRED_COLUMNS))
    except (pa.ArrowException, OSError, ValueError):
        raise _bad(name, "unreadable columns", _WRITTEN_BY) from None
    col: dict[str, FloatArray] = {}
    for c in REQUIRED_COLUMNS:
        column = table.column(c)
        if column.null_count:
            raise _bad(name, f"{c}: {column.null_count} empty values", "a number in every row")
        values = np.asarray(column.to_numpy(), dtype=np.float64)
        bad = ~np.isfinite(values)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise _bad(name, f"row {k + 1}, {c} = {values[k]}", "finite numbers")
        col[c] = values
    return recorded, col


def read_trajectory(
    path: str | os.PathLike[str], params: OrthoglideParams | None = None
) -> PlannedTrajectory:
    """Read and check a planned trajectory (see the module).

    Args:
        path: The ``trajectory.csv`` (or ``simulation.csv``) file, or its
            ``.parquet`` form (``--trajectory-format parquet``, the
            ``[tables]`` extra), of which only the columns needed are read.
        params: The machine it is played on, the prototype when ``None``: the
            file must record its design, and its points lie in its cube.

    Raises:
        InvalidParameterError: One line naming the file and what is wrong.
        DesignMismatchError: The file was made for another design, or records none.
        MissingExtraError: A Parquet file without pyarrow (the ``[tables]`` extra).
    """
    if isinstance(params, Cube):  # a cube alone cannot say which machine
        raise InvalidParameterError(
            "params", params, "the machine's OrthoglideParams (its design and its cube), or None"
        )
    params = as_params(params)
    cube = params.workspace
    name = os.fspath(path)
    parquet = isinstance(name, str) and name.lower().endswith(PARQUET_SUFFIX)
    if parquet:
        recorded, col = _parquet_columns(name)
        where = f"the metadata key '{METADATA_KEY}' = '{CSV_DESIGN_PREFIX} {{digest}}'"
    else:
        recorded, col = _csv_columns(name)
        where = f"'{CSV_DESIGN_PREFIX} {{digest}}' first"
    steps = np.diff(col["t"])
    if (steps <= 0).any():
        k = int(np.flatnonzero(steps <= 0)[0]) + 2
        raise _bad(name, f"row {k}, t = {col['t'][k - 1]:.9g}", "strictly increasing times [s]")
    if (col["path_speed"] < 0).any():
        k = int(np.flatnonzero(col["path_speed"] < 0)[0])
        raise _bad(name, f"row {k + 1}, path_speed < 0", "path speeds >= 0 [m/s]")
    check_design(  # a trajectory, of this machine
        None if recorded is None else recorded[0],
        params,
        name,
        leg_length=None if recorded is None else recorded[1],
        line=where,
        redo="run orthoglide plan (or simulate) again with this design",
    )
    p = np.column_stack([col["x"], col["y"], col["z"]])
    lo, hi = cube.q1 - CUBE_TOL, cube.q2 + CUBE_TOL
    out = ((p < lo) | (p > hi)).any(axis=1)
    if out.any():
        k = int(np.flatnonzero(out)[0])
        mm = ", ".join(f"{1e3 * v:.3f}" for v in p[k])
        raise _bad(
            name,
            f"row {k + 1}, point ({mm}) mm",
            f"points in the machine's cube, {cube.describe()} (the plan of another machine?)",
        )
    return PlannedTrajectory(col["t"], p, col["path_speed"])


def feed_colors(speed: FloatArray, top: float | None = None) -> FloatArray:
    """RGB colours in [0, 1] of path speeds [m/s], 0 to ``top`` (default: the largest), (N, 3)."""
    from orthoglide_pin.viewer.overlays import colors

    hi = float(np.max(speed)) if top is None else float(top)
    return colors(speed, 0.0, hi if hi > 0.0 else 1.0, FEED_COLORMAP)


def feed_legend(speed: FloatArray, top: float | None = None) -> dict[str, Any]:
    """Legend swatches of the feed: ``"feed 0 mm/min"`` ... ``top``, evenly spaced.

    Args:
        speed: Path speeds [m/s], (N,).
        top: The top of the scale [m/s] (default: the largest of ``speed``).
    """
    hi = float(np.max(speed)) if top is None else float(top)
    values = np.linspace(0.0, hi, FEED_SWATCHES)
    rgb = feed_colors(values, hi)
    return {f"feed {quantity('feed', v, '.0f')}": rgb[k] for k, v in enumerate(values)}
