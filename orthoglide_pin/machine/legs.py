"""The as-built geometry of the three legs, as the description takes it.

A built machine differs from its drawing leg by leg (see
:mod:`orthoglide_pin.calibration.model`): each rail is displaced (its
carriage reference point ``a_i`` is not ``-L e_i``), tilted (the slider moves
along ``u_i``, not ``e_i``), and each leg's bars have their own length
``L_i``. :class:`LegGeometry` holds these as the description's per-leg xacro
arguments (``leg<i>_offset``, ``leg<i>_axis``, ``leg<i>_length``), so that
:func:`~orthoglide_pin.machine.description.render_urdf` draws the built
machine and the closed-loop Pinocchio model solves it for real. The carriage
keeps the drawing's orientation: only the direction of its travel changes, so
the leg's revolute axes stay those of the drawing and the platform still only
translates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import finite_rows, finite_vector, float_array, positive_length
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]

#: Largest rail displacement accepted [m].
MAX_OFFSET: Final[float] = 0.05
#: Largest tilt of a rail from its drawn axis [rad].
MAX_TILT: Final[float] = 0.2
#: Tolerance on the unit length of a slider direction.
UNIT_TOL: Final[float] = 1e-9
_CYCLIC: Final = ((0, 1, 2), (1, 2, 0), (2, 0, 1))
#: The description's per-leg arguments (defaults: the drawing, ``""`` length = L).
LEG_ARGUMENTS: Final[tuple[str, ...]] = tuple(
    f"leg{i}_{what}" for i in (1, 2, 3) for what in ("offset", "axis", "length")
)


def _number(value: float) -> str:
    """``repr`` of a float, whole numbers as integers (the drawing's ``1 0 0``)."""
    v = float(value)
    return str(int(v)) if v.is_integer() else repr(v)


@dataclass(frozen=True)
class LegGeometry:
    """Per-leg geometry of a built machine, against its drawing.

    Attributes:
        offsets: Displacement of each leg's carriage reference point from the
            drawing's, world frame [m], rows per leg, shape (3, 3).
        axes: Unit slider directions ``u_i`` in the world frame, rows, (3, 3).
        lengths: Bar lengths ``L_i`` [m], shape (3,).
    """

    offsets: FloatArray
    axes: FloatArray
    lengths: FloatArray

    def __post_init__(self) -> None:
        offsets = finite_rows("offsets", self.offsets, 3, "[m]").reshape(-1, 3)
        axes = finite_rows("axes", self.axes, 3).reshape(-1, 3)
        lengths = finite_vector("lengths", self.lengths, 3, "[m]")
        if offsets.shape != (3, 3) or axes.shape != (3, 3):
            raise InvalidParameterError("offsets/axes", (offsets.shape, axes.shape), "(3, 3) each")
        if np.any(np.abs(offsets) > MAX_OFFSET):
            raise InvalidParameterError("offsets", offsets, f"within +-{MAX_OFFSET} m")
        if np.any(np.abs(np.linalg.norm(axes, axis=1) - 1.0) > UNIT_TOL):
            raise InvalidParameterError("axes", axes, "unit vectors")
        if np.any(np.diag(axes) < math.cos(MAX_TILT)):
            raise InvalidParameterError("axes", axes, f"within {MAX_TILT} rad of e_1, e_2, e_3")
        if np.any(lengths <= 0.0):
            raise InvalidParameterError("lengths", lengths, "positive lengths [m]")
        for name, value in (("offsets", offsets), ("axes", axes), ("lengths", lengths)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @classmethod
    def drawing(cls, leg_length: float) -> LegGeometry:
        """The drawing's legs: no offset, ``u_i = e_i``, ``L_i = L``."""
        length = positive_length("leg_length", leg_length)
        return cls(np.zeros((3, 3)), np.eye(3), np.full(3, length))

    @classmethod
    def from_points(
        cls, anchors: ArrayLike, axes: ArrayLike, lengths: ArrayLike, leg_length: float
    ) -> LegGeometry:
        """From the carriage reference points ``a_i`` [m] of a drawing of leg ``L``."""
        a = _square("anchors", anchors, "[m]")
        length = positive_length("leg_length", leg_length)
        return cls(a + length * np.eye(3), _square("axes", axes, ""),
                   finite_vector("lengths", lengths, 3, "[m]"))  # fmt: skip

    def xacro_args(self) -> dict[str, str]:
        """The description's per-leg arguments (the axis in each leg's own frame)."""
        args: dict[str, str] = {}
        for i, j, k in _CYCLIC:
            u = self.axes[i]
            args[f"leg{i + 1}_offset"] = " ".join(_number(v) for v in self.offsets[i])
            args[f"leg{i + 1}_axis"] = " ".join(_number(u[m]) for m in (i, j, k))
            args[f"leg{i + 1}_length"] = repr(float(self.lengths[i]))
        return args


def _square(name: str, value: ArrayLike, unit: str) -> NDArray[np.float64]:
    """``value`` as a (3, 3) array of finite floats, one row per leg, else an error naming it."""
    arr = float_array(value)
    if arr.shape != (3, 3) or not np.isfinite(arr).all():
        raise InvalidParameterError(name, value, " ".join(("3 x 3 finite numbers", unit)).strip())
    return arr
