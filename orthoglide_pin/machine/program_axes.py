"""A design's program axes: where a part program's X, Y, Z lie on the world axes.

A signed permutation of the world axes e1, e2, e3, given as three signed
1-based indices (``(2, 1, -3)``: X on +e2, Y on +e1, Z on -e3), that must be a
rotation (a mirror would cut the mirror image of the part). The
:mod:`orthoglide_pin.program` layer applies it
(:class:`~orthoglide_pin.program.axes.ProgramAxes`).
"""

from __future__ import annotations

from typing import Any, Final

from orthoglide_pin.exceptions import InvalidParameterError

#: Program X, Y, Z on the world axes of every design so far: signed, 1-based
#: (X on +e2, Y on +e1, Z on -e3: program Z up, the world's e3 pointing down).
PROTOTYPE_PROGRAM_AXES: Final = (2, 1, -3)


def program_axes_value(value: Any) -> tuple[int, int, int]:
    """``value`` as program axes: three signed 1-based world axes, a rotation.

    Raises:
        InvalidParameterError: Not three signed axes 1 to 3, each once, or a mirror.
    """
    allowed = "three signed world axes, a rotation, e.g. [2, 1, -3]"
    if isinstance(value, str):
        value = value.replace(",", " ").split()
    try:
        axes = tuple(int(v) for v in value)
        whole = all(float(v) == int(v) for v in value) and len(axes) == 3
    except (TypeError, ValueError):
        whole = False
    if not whole or sorted(abs(a) for a in axes) != [1, 2, 3]:
        raise InvalidParameterError("program_axes", value, allowed)
    matrix = [[0] * 3 for _ in range(3)]
    for col, a in enumerate(axes):
        matrix[abs(a) - 1][col] = 1 if a > 0 else -1
    det = (
        matrix[0][0] * (matrix[1][1] * matrix[2][2] - matrix[1][2] * matrix[2][1])
        - matrix[0][1] * (matrix[1][0] * matrix[2][2] - matrix[1][2] * matrix[2][0])
        + matrix[0][2] * (matrix[1][0] * matrix[2][1] - matrix[1][1] * matrix[2][0])
    )
    if det != 1:
        raise InvalidParameterError("program_axes", value, allowed + " (not a mirror)")
    return (axes[0], axes[1], axes[2])
