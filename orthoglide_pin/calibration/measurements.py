"""Measurement files: slider values and measured tool positions, checked.

A measurement file is a CSV with a header row and at least the columns
``q1,q2,q3,x,y,z``, all in metres: the slider values as commanded (or read
from the encoders) and the tool position measured in the world frame (origin
at the isotropic point, axes along the sliders). Other columns are ignored.
Blank lines and lines starting with ``#`` are skipped. A first line
``# orthoglide design: DIGEST, leg_length: L`` (the first line of the
``poses.csv`` of ``orthoglide calibrate --plan``, kept) records the design the
poses were measured on (:attr:`Measurements.design`): a calibration of another
design refuses it. A file without one (a tracker's own export) records none
and is taken for the design it is calibrated with.

Refused, with one line naming the row (0-based, counting data rows only, as in
the outputs) or the column:

* a missing column, a row of the wrong length, a value that is not a number,
  NaN or infinite;
* values in millimetres: a coordinate or slider value beyond ``MAX_COORDINATE``
  (no pose of a machine of this kind is that far from its isotropic point);
* fewer than :data:`~orthoglide_pin.calibration.identification.MIN_POSES` rows;
* two identical rows (a pose pasted twice weighs twice in the fit).
"""

from __future__ import annotations

import csv
import hashlib
import io
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._io import decode_text, not_text, read_input_bytes
from orthoglide_pin._validation import instance_of
from orthoglide_pin._validation import text as text_argument
from orthoglide_pin.calibration.identification import MIN_POSES
from orthoglide_pin.exceptions import (
    MAX_PATH_CHARS,
    CalibrationError,
    InvalidParameterError,
    cut_text,
    path_repr,
    short_repr,
)
from orthoglide_pin.machine.digest import check_design, read_design_comment
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: The columns every measurement file has, in metres.
COLUMNS: Final[tuple[str, ...]] = ("q1", "q2", "q3", "x", "y", "z")
#: Largest accepted coordinate or slider value [m]: a value beyond it was
#: almost surely written in millimetres.
MAX_COORDINATE: Final[float] = 5.0
#: Most rows accepted.
MAX_ROWS: Final[int] = 100_000
#: Largest measurement file read [bytes].
MAX_BYTES: Final[int] = 20_000_000


@dataclass(frozen=True)
class Measurements:
    """Poses read from a measurement file.

    Attributes:
        q: Slider values [m], shape (N, 3).
        points: Measured tool positions [m], shape (N, 3).
        sha256: Hash of the file's bytes, hex, to tie a calibration to its data.
        source: Where the poses came from (a file name), for messages.
        design: The design digest the file records (its first line), or
            ``None`` when it records none.
        leg_length: The leg length it records with the digest [m], or ``None``.
    """

    q: FloatArray
    points: FloatArray
    sha256: str
    source: str = "measurements"
    design: str | None = None
    leg_length: float | None = None

    def __len__(self) -> int:
        return len(self.q)


def read_measurements(path: str | os.PathLike[str]) -> Measurements:
    """Read and check a measurement CSV (see the module).

    Args:
        path: The file: a regular file (a symbolic link to one is followed) of
            at most :data:`MAX_BYTES`; a directory, a FIFO, a device or a
            socket is refused before any read.

    Raises:
        InvalidParameterError: The file cannot be read.
        CalibrationError: Its content is refused (one line, naming the row).
    """
    data = read_input_bytes(path, "measurements", MAX_BYTES)
    decode_text(data, "measurements", Path(os.fspath(path)))  # text, before any parsing
    return parse_measurements(data, os.fspath(path))


def parse_measurements(data: bytes, source: str = "measurements") -> Measurements:
    """Parse and check the bytes of a measurement CSV (see the module).

    Args:
        data: The file's content (UTF-8, a byte-order mark allowed).
        source: Its name, shown in the errors.

    Raises:
        CalibrationError: Any of the module's refusals, one line.
    """
    data = instance_of("data", data, bytes, "the file's bytes")
    source = text_argument("source", source)
    where = source if len(source) <= MAX_PATH_CHARS else path_repr(source)  # in the messages
    why = not_text(data)
    if why is not None:
        raise CalibrationError(f"{where}: not a text file ({why}): expected UTF-8 CSV text")
    text = data.decode("utf-8-sig")
    lines = [ln for ln in text.splitlines() if ln.strip()]
    try:
        design = read_design_comment(lines[0], "design") if lines else None
    except InvalidParameterError as exc:
        raise CalibrationError(f"{where}: first line: {exc}") from None
    lines = [ln for ln in lines if not ln.lstrip().startswith("#")]
    if not lines:
        raise CalibrationError(f"{where}: empty: expected a header {','.join(COLUMNS)}")
    try:
        rows = list(csv.reader(io.StringIO("\n".join(lines))))
    except csv.Error as exc:  # a field beyond the csv module's limit (128 kB)
        raise CalibrationError(
            f"{where}: not a CSV table of numbers ({cut_text(str(exc))})"
        ) from None
    header = [h.strip() for h in rows[0]]
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise CalibrationError(
            f"{where}: missing column(s) {', '.join(missing)}: the header must name "
            f"{','.join(COLUMNS)} (in metres), it has {short_repr(','.join(header))}",
            missing,
        )
    index = [header.index(c) for c in COLUMNS]
    body = rows[1:]
    if len(body) > MAX_ROWS:
        raise CalibrationError(f"{where}: {len(body)} rows, at most {MAX_ROWS}", len(body))
    values = np.empty((len(body), 6))
    for r, row in enumerate(body):
        if len(row) != len(header):
            raise CalibrationError(
                f"{where}: row {r} has {len(row)} fields, the header {len(header)}", r
            )
        for c, k in enumerate(index):
            try:
                v = float(row[k])
            except ValueError:
                raise CalibrationError(
                    f"{where}: row {r}, column {COLUMNS[c]}: {short_repr(row[k])} is not a number",
                    r,
                ) from None
            if not math.isfinite(v):
                raise CalibrationError(
                    f"{where}: row {r}, column {COLUMNS[c]}: {v} (values must be finite)", r
                )
            values[r, c] = v
    _check_values(values, where)
    return Measurements(
        q=np.ascontiguousarray(values[:, :3]),
        points=np.ascontiguousarray(values[:, 3:]),
        sha256=hashlib.sha256(data).hexdigest(),
        source=source,
        design=None if design is None else design[0],
        leg_length=None if design is None else design[1],
    )


def check_measured_design(data: Measurements, params: OrthoglideParams | None) -> None:
    """Refuse measurements that record another design than ``params`` (none: accepted).

    Raises:
        DesignMismatchError: One line naming both designs.
    """
    if data.design is not None:  # measured on the poses of a design: it must be this one
        check_design(
            data.design,
            params,
            data.source,
            leg_length=data.leg_length,
            line="'# orthoglide design: {digest}' first",
            redo="measure the poses of this design (orthoglide calibrate --plan N)",
        )


def _check_values(values: FloatArray, where: str) -> None:
    """Refuse millimetres, too few rows and duplicated rows."""
    big = np.abs(values) > MAX_COORDINATE
    if big.any():
        r, c = np.argwhere(big)[0]
        raise CalibrationError(
            f"{where}: row {r}, column {COLUMNS[c]} = {values[r, c]:g}: beyond "
            f"{MAX_COORDINATE:g} m; the file must be in metres (millimetres? divide by 1000)",
            int(r),
        )
    if len(values) < MIN_POSES:
        raise CalibrationError(
            f"{where}: {len(values)} rows, at least {MIN_POSES} poses are needed "
            "(about 60 spread over the cube identify every parameter)",
            len(values),
        )
    _, first, counts = np.unique(values, axis=0, return_index=True, return_counts=True)
    if (counts > 1).any():
        row = values[first[np.argmax(counts > 1)]]
        same = np.flatnonzero((values == row).all(axis=1))
        raise CalibrationError(
            f"{where}: rows {int(same[0])} and {int(same[1])} are identical "
            "(a pose given twice weighs twice in the fit): remove the copy",
            [int(i) for i in same],
        )
