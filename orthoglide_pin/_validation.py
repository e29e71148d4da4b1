"""Input checks shared by the modules: convert, or name the bad value."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]


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
