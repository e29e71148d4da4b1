"""The machine an entry point is given: parameters, a model, or the prototype (machine.coerce)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machine.closed_loop import as_model
from orthoglide_pin.machine.coerce import as_params, is_model

#: A design other than the prototype: longer legs, its cube moved and shrunk.
OTHER = {"leg_length": 0.36, "workspace_corner": (-0.06, -0.05, -0.07), "workspace_side": 0.15}
#: Agreement of the projected Jacobian with the closed form [-].
JACOBIAN_TOL = 1e-9
#: A tool point inside both machines' cubes [m].
POINT = np.array([0.02, -0.01, 0.03])


@pytest.fixture(scope="module")
def other() -> og.OrthoglideParams:
    return og.prototype().replace(**OTHER)


def test_parameters_are_themselves_and_none_is_the_prototype(other: og.OrthoglideParams) -> None:
    assert as_params(other) is other
    assert as_params(None) == og.prototype()


def test_a_model_is_itself_and_parameters_build_theirs(
    model: og.ClosedLoopModel, other: og.OrthoglideParams
) -> None:
    assert as_model(model) is model and is_model(model)
    built = as_model(other)
    assert isinstance(built, og.ClosedLoopModel) and built.params == other
    # the model is that design's: its Jacobian is the closed form's with L = 0.36
    q = built.solve(og.inverse_kinematics(POINT, other.leg_length)).q
    np.testing.assert_allclose(
        built.jacobian(q), og.jacobian(POINT, other.leg_length), rtol=0, atol=JACOBIAN_TOL
    )
    assert not np.allclose(built.jacobian(q), og.jacobian(POINT, 0.31), atol=1e-3)
    assert as_model(None).params == og.prototype()


@pytest.mark.parametrize("bad", ["prototype", {"leg_length": 0.31}, 0.31, np.zeros(3)])
def test_anything_else_is_refused_naming_the_argument(bad: object) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        as_params(bad, "base")
    assert info.value.name == "base" and type(bad).__name__ in str(info.value)
    assert "OrthoglideParams" in str(info.value)
    with pytest.raises(og.InvalidParameterError) as info:
        as_model(bad, "machine")
    assert info.value.name == "machine" and "ClosedLoopModel" in str(info.value)
    assert not is_model(bad)


def test_the_parameters_route_does_not_import_pinocchio() -> None:
    code = (
        "import sys; from orthoglide_pin.machine.coerce import as_params, is_model; "
        "as_params(None); assert not is_model(object()); "
        "assert 'pinocchio' not in sys.modules, 'pinocchio imported'"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)


def test_every_loader_takes_the_parameters_of_another_design(other: og.OrthoglideParams) -> None:
    model = og.load_closed_loop(other)
    assert model.params == other
    pin_model, _ = og.load_pinocchio(other)
    assert pin_model.nv == model.nv
    assert og.render_urdf(other) == model.urdf
