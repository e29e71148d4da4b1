"""The program's axes on the machine: a signed permutation, program -> world.

A part program is written in the part's frame with the ISO 841 convention:
+Z moves the tool away from the part. The machine's world frame has its own
axes e1, e2, e3; :class:`ProgramAxes` says on which world axis, and with which
sign, each program axis X, Y, Z lies. It must be a rotation (determinant +1):
a mirror would cut the mirror image of the part (a clockwise ``G2`` would turn
counter-clockwise, climb milling become conventional).

The mapping is a property of the design, its ``program_axes``
(:func:`design_axes`). Every design of the package so far shares the world
frame of the isotropic point, sliders along +e_i and gravity along +e3 (e3
points **down**, towards the table), and the default, :data:`PROTOTYPE_AXES`,
suits it: program X along +e2, Y along +e1, Z along -e3 (up).
Its X and Y keep the positive side of the prescribed cube, where it is larger
(the cube runs from -73 mm to +127 mm along each axis on the prototype).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import instance_of, points_array
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machine.program_axes import PROTOTYPE_PROGRAM_AXES

FloatArray = NDArray[np.float64]

#: Program X, Y, Z on the world axes: signed 1-based indices (2 is +e2, -3 is -e3).
PROTOTYPE_AXES: Final = PROTOTYPE_PROGRAM_AXES


@dataclass(frozen=True)
class ProgramAxes:
    """A signed permutation program -> world (see the module).

    Attributes:
        mapping: For program X, Y, Z the world axis, 1-based and signed:
            ``(2, 1, -3)`` puts X on +e2, Y on +e1 and Z on -e3.
    """

    mapping: tuple[int, int, int] = PROTOTYPE_AXES

    def __post_init__(self) -> None:
        m = tuple(self.mapping) if isinstance(self.mapping, (tuple, list)) else ()
        ok = len(m) == 3 and all(
            isinstance(x, (int, np.integer)) and not isinstance(x, bool) for x in m
        )
        if not ok or sorted(abs(int(x)) for x in m) != [1, 2, 3]:
            raise InvalidParameterError(
                "mapping", self.mapping, "a signed permutation of 1, 2, 3, e.g. (2, 1, -3)"
            )
        object.__setattr__(self, "mapping", tuple(int(x) for x in m))
        if round(float(np.linalg.det(self.matrix))) != 1:
            raise InvalidParameterError(
                "mapping", self.mapping, "a rotation (determinant +1), not a mirror"
            )

    @property
    def matrix(self) -> FloatArray:
        """``R`` with ``world = R @ program``, shape (3, 3)."""
        r = np.zeros((3, 3))
        for col, axis in enumerate(self.mapping):
            r[abs(axis) - 1, col] = 1.0 if axis > 0 else -1.0
        return r

    def to_world(self, points: ArrayLike) -> FloatArray:
        """World coordinates of program-axis points [m], shape (..., 3)."""
        return np.asarray(points_array(points, "points") @ self.matrix.T, dtype=np.float64)

    def to_program(self, points: ArrayLike) -> FloatArray:
        """Program-axis coordinates of world points [m], shape (..., 3)."""
        return np.asarray(points_array(points, "points") @ self.matrix, dtype=np.float64)

    def describe(self) -> str:
        """E.g. ``X -> +e2, Y -> +e1, Z -> -e3``."""
        return ", ".join(
            f"{name} -> {'+' if a > 0 else '-'}e{abs(a)}"
            for name, a in zip("XYZ", self.mapping, strict=True)
        )


def design_axes(params: OrthoglideParams | None = None) -> ProgramAxes:
    """The program axes of a design: its ``program_axes`` (see the module).

    Args:
        params: The design (``None``: the prototype's, :data:`PROTOTYPE_AXES`).

    Raises:
        InvalidParameterError: ``params`` is not an OrthoglideParams.
    """
    if params is None:
        return ProgramAxes(PROTOTYPE_AXES)
    params = instance_of("params", params, OrthoglideParams, "OrthoglideParams or None")
    return ProgramAxes(params.program_axes)
