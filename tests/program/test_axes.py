"""Program axes on the machine: a rotation, program Z up on the prototype."""

from __future__ import annotations

import numpy as np
import pytest

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.program.axes import PROTOTYPE_AXES, ProgramAxes, design_axes


def test_the_prototype_program_z_points_up() -> None:
    axes = design_axes()
    assert axes.mapping == PROTOTYPE_AXES
    # world e3 points down (gravity): program +Z is world -e3
    np.testing.assert_array_equal(axes.to_world([0.0, 0.0, 1.0]), [0.0, 0.0, -1.0])
    assert np.linalg.det(axes.matrix) == pytest.approx(1.0)
    p = np.array([[1.0, 2.0, 3.0], [-4.0, 5.0, 6.0]])
    np.testing.assert_array_equal(axes.to_program(axes.to_world(p)), p)
    assert axes.describe() == "X -> +e2, Y -> +e1, Z -> -e3"


@pytest.mark.parametrize("mapping", [(1, 2, -3), (1, 1, 3), (1, 2), (0, 1, 2), (1.5, 2, 3)])
def test_a_mirror_or_not_a_permutation_is_refused(mapping) -> None:
    with pytest.raises(InvalidParameterError):
        ProgramAxes(mapping)


def test_the_axes_are_a_property_of_the_design(tmp_path) -> None:
    import orthoglide_pin as og

    params = og.prototype().replace(program_axes=[1, -2, -3])
    assert design_axes(params).mapping == (1, -2, -3)
    assert og.OrthoglideParams.from_yaml(params.to_yaml()).program_axes == (1, -2, -3)
    assert "program_axes" not in og.prototype().to_dict()  # the default is not written
    with pytest.raises(InvalidParameterError, match="program_axes"):
        og.prototype().replace(program_axes=(1, 2, -3))  # a mirror
    # a program read on that design: program Y on world -e2
    block = og.read_program("G0 Y10\n", axes=design_axes(params)).blocks[0]
    np.testing.assert_allclose(block.end, [0.0, -0.01, 0.0])
