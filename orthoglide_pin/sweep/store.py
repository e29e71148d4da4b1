"""A sweep's directory: its record, its parts, and what counts as an earlier sweep.

A sweep writes, under its directory (:func:`~orthoglide_pin.sweep.runner.run_sweep`),
``sweep.json``, the record of its spec (:meth:`~orthoglide_pin.sweep.spec.SweepSpec.to_dict`),
and one part per finished design, ``parts/<key>.json``. This module decides
what of it may be trusted:

* **An earlier sweep** is recognised by the package's marker
  (:data:`~orthoglide_pin._paths.MARKER_NAME`), or by a ``sweep.json`` of the
  package's own schema (:func:`is_record`: a JSON object with an integer
  ``schema`` of this package, one of its modes, its axes and settings). A
  directory that merely holds some file named ``sweep.json`` is not one.
* **One directory, one spec.** A sweep into the directory of an earlier sweep
  with another spec is refused before anything is written
  (:func:`check_spec`), naming what differs; the same spec carries it on.
* **A part counts only when complete against the spec** (:func:`part_problem`):
  a JSON object whose key is its design's, whose ``mode`` and axis values are
  the design's, with every column of the table (``status = "ok"``) or the
  design's own columns and a message (``"invalid"``), each of the right type
  (numbers or ``null`` for NaN, ``bounds_hold`` a boolean). Any other part,
  damaged, truncated or hand-edited, is computed again and replaced.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Final

from orthoglide_pin._io import atomic_write_text, json_text
from orthoglide_pin.exceptions import OutputPathError, short_repr
from orthoglide_pin.sweep.program import PROGRAM_TEXT_COLUMNS
from orthoglide_pin.sweep.spec import MODES, SCHEMA, SweepSpec, design_key
from orthoglide_pin.sweep.table import table_columns

PARTS: Final = "parts"
SPEC_NAME: Final = "sweep.json"
#: What a sweep writes in its directory (listed by the directory's marker).
OWN_NAMES: Final = ("sweep.json", PARTS, "results.csv", "results.parquet", "sweep.png")
#: Keys of every record the package writes (``schema`` 1 and later).
RECORD_KEYS: Final = frozenset(
    {"schema", "mode", "axes", "base", "cube_side", "cube_corner", "grid", "requirement_grid"}
)
#: Keys of the record that describe, but do not define, the sweep (not compared).
DESCRIPTIVE_KEYS: Final = frozenset({"stiffness_assumptions"})
#: Largest record read [bytes] (a record is a few kB).
MAX_RECORD_BYTES: Final[int] = 1 << 20
#: Differences named in a refusal.
MAX_NAMED: Final[int] = 3
#: Columns that every built design has, as finite numbers.
BUILT_COLUMNS: Final = (
    "leg_length",
    "cube_side",
    "slider_lower",
    "slider_upper",
    "stroke",
    "ratio",
    "moving_mass",
)
_TEXT_COLUMNS: Final = ("key", "status", "error", "mode")
_STATUSES: Final = ("ok", "invalid")


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def is_record(data: Any) -> bool:
    """Whether ``data`` (parsed JSON) is a sweep record of the package's own schema."""
    if not isinstance(data, dict) or not data.keys() >= RECORD_KEYS:
        return False
    schema, axes = data["schema"], data["axes"]
    return (
        isinstance(schema, int)
        and not isinstance(schema, bool)
        and 1 <= schema <= SCHEMA
        and data["mode"] in MODES
        and isinstance(axes, dict)
        and all(isinstance(v, list) and all(_number(x) for x in v) and v for v in axes.values())
        and isinstance(data["base"], dict)
    )


def read_record(out: str | Path) -> dict[str, Any] | None:
    """The record ``out/sweep.json`` when it is one of the package's (see :func:`is_record`)."""
    path = Path(out) / SPEC_NAME
    try:
        if not path.is_file() or path.stat().st_size > MAX_RECORD_BYTES:
            return None
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):  # unreadable, not UTF-8, not JSON
        return None
    return data if is_record(data) else None


def is_earlier_sweep(out: str | Path) -> bool:
    """Whether ``out`` holds the record of an earlier sweep (a marker is checked apart)."""
    return read_record(out) is not None


def _differences(now: Any, then: Any, where: str) -> list[str]:
    if isinstance(now, dict) and isinstance(then, dict):
        out = []
        for name in sorted(now.keys() | then.keys()):
            if where == "" and name in DESCRIPTIVE_KEYS:
                continue
            here = f"{where}.{name}" if where else name
            if name not in then:
                out.append(f"{here}: {short_repr(now[name])} now, absent there")
            elif name not in now:
                out.append(f"{here}: absent now, {short_repr(then[name])} there")
            else:
                out += _differences(now[name], then[name], here)
        return out
    return [] if now == then else [f"{where}: {short_repr(now)} now, {short_repr(then)} there"]


def spec_differences(spec: SweepSpec, record: Mapping[str, Any]) -> list[str]:
    """What differs between ``spec`` and a sweep record, one ``"name: now, there"`` each."""
    now = json.loads(json_text(spec.to_dict()))  # as it would be written: NaN as null
    return _differences(now, dict(record), "")


def check_spec(out: str | Path, spec: SweepSpec) -> None:
    """Refuse a sweep into the directory of an earlier sweep with another spec.

    Raises:
        OutputPathError: ``out`` holds the record of a sweep whose spec differs;
            the message names the first differences. Nothing is written.
    """
    record = read_record(out)
    if record is None:
        return
    found = spec_differences(spec, record)
    if found:
        more = f" (and {len(found) - MAX_NAMED} more)" if len(found) > MAX_NAMED else ""
        raise OutputPathError(
            out,
            "it holds an earlier sweep with another spec ("
            + "; ".join(found[:MAX_NAMED])
            + more
            + "); nothing was written: choose a new directory, or run the same sweep "
            "to carry it on",
        )


def part_problem(row: Any, design: Mapping[str, Any]) -> str | None:
    """Why a part is not a complete row of ``design``, or ``None`` when it is (see the module)."""
    if not isinstance(row, dict):
        return "not a JSON object"
    if row.get("key") != design_key(design):
        return "the key of another design"
    status, error = row.get("status"), row.get("error")
    if status not in _STATUSES:
        return f"status {short_repr(status)}, not 'ok' or 'invalid'"
    if not isinstance(error, str) or (error == "") != (status == "ok"):
        return f"error {short_repr(error)} for status {short_repr(status)}"
    if row.get("mode") != design["mode"]:
        return f"mode {short_repr(row.get('mode'))}, not {design['mode']!r}"
    names = list(design["values"])
    for name, value in design["values"].items():
        if row.get(name) != value:
            return f"{name} {short_repr(row.get(name))}, not the design's {value!r}"
    columns = table_columns(
        names, design.get("program") is not None, design.get("cut") is not None
    )
    required = columns if status == "ok" else [*_TEXT_COLUMNS, *names]
    missing = [c for c in required if c not in row]
    if missing:
        return "no " + ", ".join(missing[:MAX_NAMED]) + (" ..." if len(missing) > 3 else "")
    for name in columns:
        if name in _TEXT_COLUMNS or name not in row:
            continue
        if name in PROGRAM_TEXT_COLUMNS:
            if not (isinstance(row[name], str) or (row[name] is None and status == "invalid")):
                return f"{name} {short_repr(row[name])}, not a text"
            continue
        value = row[name]
        if name == "bounds_hold":
            if not (isinstance(value, bool) or (value is None and status == "invalid")):
                return f"bounds_hold {short_repr(value)}, not a boolean"
        elif not (value is None or _number(value)):
            return f"{name} {short_repr(value)}, not a number"
    if status == "ok":
        for name in BUILT_COLUMNS:
            if row[name] is None or not math.isfinite(row[name]):
                return f"{name} {short_repr(row[name])}, not a finite number"
    return None


def read_part(path: Path, design: Mapping[str, Any]) -> dict[str, Any] | None:
    """The part at ``path`` when it is a complete row of ``design``, else ``None``."""
    try:
        row = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None  # unreadable: computed again
    return row if part_problem(row, design) is None else None


def load_parts(out: str | Path, designs: Sequence[Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    """The complete rows among ``designs`` found under ``out/parts`` (key to row).

    Args:
        out: The sweep's directory.
        designs: Designs of :meth:`~orthoglide_pin.sweep.spec.SweepSpec.designs`.

    Returns:
        Key to row, for each design whose part is complete (see :func:`part_problem`).
    """
    folder = Path(out) / PARTS
    found = {}
    for design in designs:
        key = design_key(design)
        path = folder / f"{key}.json"
        if path.is_file():
            row = read_part(path, design)
            if row is not None:
                found[key] = row
    return found


def write_part(out: str | Path, row: Mapping[str, Any]) -> Path:
    """Write one finished row to ``out/parts/<key>.json`` atomically; return the path."""
    path = Path(out) / PARTS / f"{row['key']}.json"
    atomic_write_text(path, json_text(dict(row)) + "\n")  # NaN metrics as null
    return path


__all__ = [
    "OWN_NAMES",
    "PARTS",
    "SPEC_NAME",
    "check_spec",
    "is_earlier_sweep",
    "is_record",
    "load_parts",
    "part_problem",
    "read_record",
    "spec_differences",
    "write_part",
]
