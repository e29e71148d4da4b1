"""Input checks shared by the modules: convert, or name the bad value."""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Mapping
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]
T = TypeVar("T")

#: Range of every length [m] and coordinate (within +-MAX_LENGTH) accepted by
#: the kinematic functions: squares and cubes of such values stay far from
#: overflow and underflow, and no machine of this kind is 1 km long.
MIN_LENGTH = 1e-9
MAX_LENGTH = 1e3
#: Most points (or rows) of one call of any vectorised function, the API grids'
#: cap: counted from the shape before the values are read.
MAX_BATCH_POINTS = 50_000_000


def float_array(value: ArrayLike) -> FloatArray:
    """``value`` as a float64 array, or an empty one when it is not numeric.

    Callers reject the empty array through their own shape check, so that a
    string or a ragged list gets the same clear error as a wrong shape.
    """
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        return np.empty(0)


def finite_vector(name: str, value: ArrayLike, size: int, unit: str = "") -> FloatArray:
    """``value`` as a vector of ``size`` finite floats.

    Args:
        name: Name of the argument, for the error message.
        value: The value to check.
        size: Required number of entries.
        unit: Unit shown in the error message, e.g. ``"[m]"``.

    Raises:
        InvalidParameterError: If ``value`` is not ``size`` finite numbers.
    """
    arr = float_array(value)
    if arr.shape != (size,) or not np.all(np.isfinite(arr)):
        allowed = f"{size} finite numbers" + (f" {unit}" if unit else "")
        raise InvalidParameterError(name, value, allowed)
    return arr


def positive_number(name: str, value: Any, allowed: str = "a positive finite number") -> float:
    """``value`` as a positive finite float (booleans and strings are refused).

    Raises:
        InvalidParameterError: Naming ``name`` and ``allowed``.
    """
    try:
        out = math.nan if isinstance(value, (bool, str)) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and out > 0.0):
        raise InvalidParameterError(name, value, allowed)
    return out


def positive_limit(name: str, value: Any) -> float:
    """``value`` as a positive limit: a finite positive float, or ``inf`` for none.

    Raises:
        InvalidParameterError: Naming ``name``.
    """
    try:
        out = math.nan if isinstance(value, (bool, np.bool_, str)) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not out > 0.0:  # NaN fails too
        raise InvalidParameterError(name, value, "a positive number (inf for no limit)")
    return out


def first_index(mask: ArrayLike) -> int:
    """Flat index of the first ``True`` entry of ``mask``."""
    return int(np.argmax(np.asarray(mask).reshape(-1)))


def points_array(values: ArrayLike, name: str, *, limit: float = MAX_LENGTH) -> FloatArray:
    """``values`` as a float64 array of shape ``(..., 3)`` of finite numbers.

    Raises:
        InvalidParameterError: On a wrong shape (naming it), more than
            :data:`MAX_BATCH_POINTS` points, or with the first
            point that has a non-finite coordinate or one beyond ``limit``
            (``MAX_LENGTH`` [m] by default: the points are positions).
    """
    arr = float_array(values)
    if arr.ndim == 0 or arr.size == 0 or arr.shape[-1] != 3:
        raise InvalidParameterError(f"{name}.shape", arr.shape, "an array of shape (..., 3)")
    size_within(name, arr.shape, arr.size // 3, MAX_BATCH_POINTS, "points")
    finite = np.isfinite(arr).all(axis=-1)
    if not finite.all():
        bad = tuple(float(v) for v in arr.reshape(-1, 3)[first_index(~finite)])
        raise InvalidParameterError(name, bad, "finite numbers")
    far = (np.abs(arr) > limit).any(axis=-1)
    if far.any():
        bad = tuple(float(v) for v in arr.reshape(-1, 3)[first_index(far)])
        raise InvalidParameterError(name, bad, f"entries within +-{limit:g}")
    return arr


def output_array(out: FloatArray | None, name: str, shape: tuple[int, ...]) -> FloatArray:
    """Validate, or allocate, an output array of the given shape (float64, C order)."""
    if out is None:
        return np.empty(shape, dtype=np.float64)
    ok = isinstance(out, np.ndarray) and out.shape == shape and out.dtype == np.float64
    if not (ok and out.flags.c_contiguous and out.flags.writeable):
        got = getattr(out, "shape", type(out).__name__)
        raise InvalidParameterError(name, got, f"a writeable C-contiguous float64 array {shape}")
    return out


def positive_length(name: str, value: Any) -> float:
    """``value`` as a length in ``[MIN_LENGTH, MAX_LENGTH]`` [m] (see :func:`positive_number`)."""
    out = positive_number(name, value, "a positive finite length [m]")
    if not MIN_LENGTH <= out <= MAX_LENGTH:
        allowed = f"a length in [{MIN_LENGTH:g}, {MAX_LENGTH:g}] m"
        raise InvalidParameterError(name, value, allowed)
    return out


def finite_rows(name: str, value: ArrayLike, width: int, unit: str = "") -> FloatArray:
    """``value`` as a C-contiguous array of ``N >= 1`` finite rows of ``width`` numbers.

    A single vector of shape ``(width,)`` is one row.

    Args:
        name: Name of the argument, for the error message.
        value: The value to check.
        width: Required number of columns.
        unit: Unit shown in the error message, e.g. ``"[m]"``.

    Raises:
        InvalidParameterError: On another shape, more than :data:`MAX_BATCH_POINTS`
            rows, or a non-finite entry.
    """
    arr = float_array(value)
    if arr.ndim == 1 and arr.size:
        arr = arr[np.newaxis]
    if arr.ndim != 2 or arr.shape[1] != width or arr.shape[0] == 0:
        allowed = f"({width},) or (N, {width}) with N >= 1" + (f" {unit}" if unit else "")
        raise InvalidParameterError(f"{name}.shape", arr.shape, allowed)
    size_within(name, arr.shape, arr.shape[0], MAX_BATCH_POINTS, "rows")
    if not np.isfinite(arr).all():
        raise InvalidParameterError(name, "non-finite values", "finite numbers")
    return np.ascontiguousarray(arr)


# ------------------------------------------------------ physical input ranges
#: Largest speed accepted as an input, tool or slider [m/s] (machine tools
#: move at a few m/s); beyond it the squared speeds of the dynamics overflow
#: long before the results mean anything.
MAX_SPEED = 1e3
#: Largest acceleration accepted as an input [m/s^2] (about 10^4 g).
MAX_ACCELERATION = 1e5
#: Largest jerk accepted as an input [m/s^3].
MAX_JERK = 1e9
#: Largest gravity accepted [m/s^2] (about 100 g).
MAX_GRAVITY = 1e3
#: Largest external force [N] and moment [N.m] accepted on the tool.
MAX_WRENCH = 1e9


def bounded_number(
    name: str, value: Any, high: float, unit: str, *, allow_zero: bool = False
) -> float:
    """``value`` as a finite float in ``(0, high]`` (``[0, high]`` with ``allow_zero``).

    Raises:
        InvalidParameterError: Naming ``name``, the range and ``unit``.
    """
    try:
        out = math.nan if isinstance(value, (bool, str)) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    low_ok = out >= 0.0 if allow_zero else out > 0.0
    if not (math.isfinite(out) and low_ok and out <= high):
        low = "[0" if allow_zero else "(0"
        raise InvalidParameterError(name, value, f"a number in {low}, {high:g}] {unit}")
    return out


def bounded_rows(name: str, value: ArrayLike, width: int, high: float, unit: str) -> FloatArray:
    """As :func:`finite_rows`, with every entry of magnitude at most ``high``.

    Raises:
        InvalidParameterError: On a bad shape, a non-finite entry, or the first
            entry beyond ``high`` (naming it and the range).
    """
    arr = finite_rows(name, value, width, unit)
    over = np.abs(arr) > high
    if over.any():
        bad = float(arr.reshape(-1)[first_index(over)])
        raise InvalidParameterError(name, bad, f"values within +-{high:g} {unit}")
    return arr


def bounded_vector(name: str, value: ArrayLike, size: int, high: float, unit: str) -> FloatArray:
    """As :func:`finite_vector`, with every entry of magnitude at most ``high``.

    Raises:
        InvalidParameterError: Naming ``name``, the value and the range.
    """
    arr = finite_vector(name, value, size, unit)
    if (np.abs(arr) > high).any():
        shown = tuple(arr.tolist())
        raise InvalidParameterError(name, shown, f"{size} numbers within +-{high:g} {unit}")
    return arr


def gravity_vector(value: ArrayLike, name: str = "gravity") -> FloatArray:
    """Gravity [m/s^2], shape (3,), of magnitude at most :data:`MAX_GRAVITY`.

    Raises:
        InvalidParameterError: Not three finite numbers, or a larger magnitude.
    """
    g = finite_vector(name, value, 3, "[m/s^2]")
    if np.abs(g).max() > MAX_GRAVITY or float(np.linalg.norm(g)) > MAX_GRAVITY:
        raise InvalidParameterError(
            name, tuple(g.tolist()), f"a vector of magnitude at most {MAX_GRAVITY:g} m/s^2"
        )
    return g


def number_in(name: str, value: Any, low: float, high: float, unit: str) -> float:
    """``value`` as a finite float in ``[low, high]`` (booleans and strings are refused).

    Raises:
        InvalidParameterError: Naming ``name``, the range and ``unit``.
    """
    try:
        out = math.nan if isinstance(value, (bool, np.bool_, str)) else float(value)
    except (TypeError, ValueError, OverflowError):
        out = math.nan
    if not (math.isfinite(out) and low <= out <= high):
        raise InvalidParameterError(name, value, f"a number in [{low:g}, {high:g}] {unit}")
    return out


def size_within(name: str, value: Any, count: float, cap: int, what: str) -> None:
    """Refuse an input that would make more than ``cap`` items, before they are made.

    Args:
        name: The argument that sets the size, for the error message.
        value: Its value.
        count: How many items it would make (a float: it may be huge or infinite).
        cap: The announced cap.
        what: What the items are, e.g. ``"points"``.

    Raises:
        InvalidParameterError: Naming ``name``, the count and the cap.
    """
    if not count <= cap:  # NaN is refused too
        shown = f"{int(count):,}" if count < 1e9 else f"{count:.3g}"  # NaN, inf: as floats
        raise InvalidParameterError(name, value, f"at most {cap:,} {what} (here {shown})")


def capped_points(values: ArrayLike, name: str, cap: int) -> FloatArray:
    """As :func:`points_array`, refusing more than ``cap`` points before reading any.

    Raises:
        InvalidParameterError: More than ``cap`` points (naming the shape), or as
            :func:`points_array`.
    """
    given = float_array(values)  # no copy of a float64 array: counted before any work
    size_within(name, given.shape, given.size // 3, cap, "points")
    return points_array(given, name)


def instance_of(name: str, value: object, cls: type[T], allowed: str) -> T:
    """``value`` itself if it is a ``cls``, else an error naming the argument.

    For API misuse (a string where parameters are expected, say): a clear
    :class:`InvalidParameterError` instead of an ``AttributeError`` from deep
    inside.

    Raises:
        InvalidParameterError: Naming ``name``, the type received and ``allowed``.
    """
    if not isinstance(value, cls):
        raise InvalidParameterError(name, value, f"{allowed}, not {type(value).__name__}")
    return value


# ------------------------------------------------ kinds of argument of the API
def flag(name: str, value: Any) -> bool:
    """``value`` as a bool: ``True`` or ``False`` (numpy's included), nothing else.

    Raises:
        InvalidParameterError: Naming ``name`` (an array or a string is not a flag).
    """
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidParameterError(name, value, "True or False")
    return bool(value)


def integer(name: str, value: Any, low: int = 1, high: int | None = None) -> int:
    """``value`` as an int in ``[low, high]`` (Python or numpy integers; no bool, no float).

    Raises:
        InvalidParameterError: Naming ``name`` and the range.
    """
    whole = isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
    if not whole or value < low or (high is not None and value > high):
        if high is not None:
            allowed = f"an integer in [{low}, {high}]"
        else:
            allowed = "a positive integer" if low == 1 else f"an integer >= {low}"
        raise InvalidParameterError(name, value, allowed)
    return int(value)


def finite_number(name: str, value: Any, unit: str = "") -> float:
    """``value`` as a finite float of any sign (booleans and strings are refused).

    Raises:
        InvalidParameterError: Naming ``name`` (and ``unit``).
    """
    try:
        out = math.nan if isinstance(value, (bool, np.bool_, str)) else float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not math.isfinite(out):
        raise InvalidParameterError(name, value, "a finite number" + (f" {unit}" if unit else ""))
    return out


def choice(name: str, value: Any, choices: Iterable[str]) -> str:
    """``value`` itself if it is one of the strings ``choices``.

    Raises:
        InvalidParameterError: Naming ``name`` and listing the choices.
    """
    allowed = tuple(choices)
    if not isinstance(value, str) or value not in allowed:
        raise InvalidParameterError(name, value, "one of " + ", ".join(map(repr, allowed)))
    return value


def text(name: str, value: Any, allowed: str = "a string") -> str:
    """``value`` itself if it is a ``str``.

    Raises:
        InvalidParameterError: Naming ``name``, the type received and ``allowed``.
    """
    return instance_of(name, value, str, allowed)


def path_argument(name: str, value: T) -> T:
    """``value`` itself if it is a file path (``str`` or ``os.PathLike``).

    Raises:
        InvalidParameterError: Naming ``name`` and the type received.
    """
    if not isinstance(value, (str, os.PathLike)):
        raise InvalidParameterError(
            name, value, f"a file path (str or os.PathLike), not {type(value).__name__}"
        )
    return value


def mapping(name: str, value: Any, allowed: str = "a mapping (dict)") -> Mapping[str, Any]:
    """``value`` itself if it is a mapping.

    Raises:
        InvalidParameterError: Naming ``name``, the type received and ``allowed``.
    """
    return instance_of(name, value, Mapping, allowed)  # type: ignore[type-abstract]


def mappings(name: str, value: Any, allowed: str = "mappings (dicts)") -> list[Mapping[str, Any]]:
    """``value`` as a list of mappings (an iterable of them, not one mapping or a string).

    Raises:
        InvalidParameterError: Naming ``name`` and ``allowed``.
    """
    if not isinstance(value, Iterable) or isinstance(value, (str, bytes, Mapping)):
        raise InvalidParameterError(name, value, allowed)
    return [mapping(name, item, allowed) for item in value]


def name_list(name: str, value: Any, allowed: str = "names (str), or one name") -> tuple[str, ...]:
    """``value`` as a tuple of strings: one string, or a list or tuple of them.

    Raises:
        InvalidParameterError: Naming ``name`` and ``allowed``.
    """
    items = (value,) if isinstance(value, str) else value
    if not isinstance(items, (tuple, list)) or not all(isinstance(i, str) for i in items):
        raise InvalidParameterError(name, value, allowed)
    return tuple(items)


def optional_callable(
    name: str, value: Any, allowed: str = "a function or None"
) -> Callable[..., Any] | None:
    """``value`` itself if it is ``None`` or callable.

    Raises:
        InvalidParameterError: Naming ``name``, the type received and ``allowed``.
    """
    if value is not None and not callable(value):
        raise InvalidParameterError(name, value, f"{allowed}, not {type(value).__name__}")
    return value  # type: ignore[no-any-return]
