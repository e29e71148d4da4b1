"""The modal frame FEA (OpenSees) against the package's full vibration model.

* the lowest six frequencies of OpenSees' model and of the full model
  (``natural_frequencies(..., model="full")``) at five points of the cube, on
  the prototype and on a second design, with and without a drive;
* the same structure with the same masses (the full model without the
  sections' rotary inertia, which OpenSees' consistent mass leaves out), cut
  alike: the two assemblies agree to the penalty stiffness and the solvers;
* the six point masses reproduce the platform's spatial inertia exactly;
* OpenSees' global model is wiped between calls; clear errors.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from elasticity._support import cube_points

import orthoglide_pin as og
from orthoglide_pin.dynamics.inertia import inertia_table
from orthoglide_pin.elasticity import frame_modes as fm
from orthoglide_pin.elasticity.frame_modal_fea import frame_fea_modes, platform_point_masses
from orthoglide_pin.elasticity.mass import (
    member_masses,
    platform_inertia,
    reflected_mass,
    spatial_inertia,
)
from orthoglide_pin.exceptions import (
    InvalidParameterError,
    MissingExtraError,
    UnreachablePointError,
)

pytest.importorskip("openseespy")

SEED = 20261202
#: The plan's agreement with the full model on the lowest six frequencies
#: (measured: 0.22 % at most; the gap is the sections' rotary inertia).
FULL_TOL = 5e-3
#: The same structure with the same masses and cut: the penalty on the skew
#: revolutes and the two eigensolvers (measured: 7e-7 at most).
SAME_MODEL_TOL = 1e-5
#: The same model twice: ARPACK's convergence from its random start vector.
REPEAT_TOL = 1e-7
#: Point masses against the spatial inertia (rounding).
EXACT_TOL = 1e-12
MODES = 6


def _designs() -> list[og.OrthoglideParams]:
    base = og.prototype()
    other = og.design_from_workspace(0.15, 0.5, 2.0).to_params(base)
    return [base, dataclasses.replace(other, bar_radius=0.012, actuator_stiffness=6e7)]


def _points(params: og.OrthoglideParams, count: int) -> np.ndarray:
    return cube_points(params, count, SEED)


@pytest.mark.parametrize(("design", "with_drive"), [(0, False), (1, True)])
def test_the_full_model_within_half_a_percent(
    design: int, with_drive: bool, drive: og.Drive
) -> None:
    params = _designs()[design]
    points = _points(params, 5)
    chosen = drive if with_drive else None
    full = og.natural_frequencies(params, points, chosen, model="full")
    assert full.segments is not None
    for k, point in enumerate(points):
        fea = og.frame_fea_modes(params, point, chosen, segments=int(full.segments[k]))
        assert fea.shape == (MODES,)
        assert np.all(np.diff(fea) >= 0.0)
        np.testing.assert_allclose(fea, full.frequencies[k], rtol=FULL_TOL)


@pytest.mark.parametrize("design", [0, 1])
def test_the_same_structure_and_masses_agree_tightly(design: int, drive: og.Drive) -> None:
    params = _designs()[design]
    table = inertia_table(params)
    masses = tuple(dataclasses.replace(m, bending=0.0) for m in member_masses(params, table))
    plat = platform_inertia(params, table)
    carriage = float(np.mean([b.mass for b in table.kind("carriage")]))
    carriage += reflected_mass(drive)
    for point in _points(params, 2):
        mats = fm.frame_matrices(point, params, masses, plat, carriage, segments=3)
        w2, _ = fm.solve_modes(mats, MODES)
        fea = frame_fea_modes(params, point, drive, segments=3)
        np.testing.assert_allclose(fea, np.sqrt(w2) / (2.0 * np.pi), rtol=SAME_MODEL_TOL)


@pytest.mark.parametrize("design", [0, 1])
def test_point_masses_carry_the_platform_inertia(design: int) -> None:
    params = _designs()[design]
    plat = platform_inertia(params, inertia_table(params))
    tool = np.array([0.01, -0.02, 0.03])
    where, masses = platform_point_masses(plat, tool)
    rebuilt = sum(
        spatial_inertia(m, xyz, np.zeros((3, 3)), tool)
        for xyz, m in zip(where, masses, strict=True)
    )
    # the spatial inertia about the tool tip is the same at every point (pure translation)
    assert np.abs(rebuilt - plat).max() <= EXACT_TOL * np.abs(plat).max()


def test_repeated_calls_start_from_a_clean_model() -> None:
    params = og.prototype()
    first = frame_fea_modes(params, params.workspace.q2, count=2, segments=2)
    frame_fea_modes(params, [0.0, 0.0, 0.0], count=4, segments=3)
    again = frame_fea_modes(params, params.workspace.q2, count=2, segments=2)
    np.testing.assert_allclose(first, again, rtol=REPEAT_TOL)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"point": [0.0, 0.0]}, InvalidParameterError, "point"),
        ({"point": [np.nan, 0.0, 0.0]}, InvalidParameterError, "point"),
        ({"point": [5.0, 0.0, 0.0]}, UnreachablePointError, "reach"),
        ({"count": 0}, InvalidParameterError, "count"),
        ({"count": 2.5}, InvalidParameterError, "count"),
        ({"segments": 0}, InvalidParameterError, "segments"),
        ({"drive": "motor"}, InvalidParameterError, "drive"),
        ({"params": {"leg_length": 0.3}}, InvalidParameterError, "params"),
    ],
)
def test_bad_input(kwargs: dict, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        frame_fea_modes(**kwargs)


def test_a_body_that_cannot_be_rigid_is_refused() -> None:
    bad = spatial_inertia(1.0, np.zeros(3), np.diag([1.0, 1.0, 3.0]), np.zeros(3))
    with pytest.raises(InvalidParameterError, match="triangle"):
        platform_point_masses(bad, np.zeros(3))
    with pytest.raises(InvalidParameterError, match="inertia"):
        platform_point_masses(np.eye(5), np.zeros(3))


def test_without_opensees_says_modal(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(__import__("sys").modules, "openseespy", None)
    monkeypatch.setitem(__import__("sys").modules, "openseespy.opensees", None)
    with pytest.raises(MissingExtraError) as info:
        frame_fea_modes()
    assert str(info.value) == (
        "the modal frame FEA check needs the optional package openseespy, which is not "
        "installed: pip install 'orthoglide-pin[modal]'"
    )
