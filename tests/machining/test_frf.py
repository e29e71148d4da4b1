"""The tool tip's modal model: the receptance's closed forms and the machine's modes at the point.

A single mode ``k``, ``zeta`` has at resonance the receptance ``-i / (2 zeta k)``
and at zero frequency ``1 / k``; modes in series add their receptances. The
machine's modes are normalised to the mass matrix, so that the sum over all of
them of ``t t^T / omega^2`` is the static compliance at the tool; with the six
lowest of the platform model's modes it is close to it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machining.frf import (
    ModalModel,
    frequency_response,
    single_mode,
    tool_tip_model,
    tool_tip_models,
)

#: Closed forms of one mode's receptance, relative (round-off only).
CLOSED_FORM_TOL = 1e-12
#: The lowest in-plane frequency of the tool-tip model against ``natural_frequencies``, [Hz].
FREQUENCY_TOL = 1e-9
#: The six lowest modes' static compliance in the feed plane against the full
#: modal sum (twelve modes of the platform model), relative.
STATIC_TOL = 0.05


def test_one_mode_receptance_closed_forms() -> None:
    mode = single_mode(500.0, 0.02, 2.0e7, "y")
    g = frequency_response(mode, [0.0, 500.0])
    assert g[0, 1, 1].real == pytest.approx(1.0 / 2.0e7, rel=CLOSED_FORM_TOL)
    assert g[1, 1, 1] == pytest.approx(-1j / (2 * 0.02 * 2.0e7), rel=CLOSED_FORM_TOL)
    assert np.all(g[:, 0, :] == 0.0)  # a Y mode does not move X


def test_modes_in_series_add_their_receptances() -> None:
    a, b = single_mode(300.0, 0.03, 1e6, "x"), single_mode(900.0, 0.01, 5e6, "x")
    f = np.linspace(10.0, 2000.0, 50)
    both = frequency_response(a.with_modes(b), f)
    assert np.allclose(both, frequency_response(a, f) + frequency_response(b, f), rtol=1e-13)


def test_rotation_turns_the_receptance() -> None:
    model = single_mode(300.0, 0.03, 1e6, "x").with_modes(single_mode(400.0, 0.03, 2e6, "y"))
    angle = 0.3
    c, s = math.cos(angle), math.sin(angle)
    rot = np.array([[c, s], [-s, c]])
    g = frequency_response(model, [350.0])[0]
    assert np.allclose(frequency_response(model.rotated(angle), [350.0])[0], rot @ g @ rot.T)


def test_bad_models_are_refused() -> None:
    with pytest.raises(og.InvalidParameterError, match="damping"):
        ModalModel(np.array([100.0]), np.array([1.5]), np.array([1.0]), np.ones((2, 1)))
    with pytest.raises(og.InvalidParameterError, match="shapes"):
        ModalModel(np.array([100.0]), np.array([0.02]), np.array([1.0]), np.ones((3, 1)))
    with pytest.raises(og.InvalidParameterError, match="direction"):
        single_mode(100.0, 0.02, 1e6, "z")


def test_machine_modes_at_the_tool() -> None:
    params = og.prototype()
    points = np.array([[0.0, 0.0, 0.0], params.workspace.q2])
    modes = og.natural_frequencies(params, points)
    models = tool_tip_models(params, points, damping=0.02)
    for model, freq in zip(models, modes.frequencies, strict=True):
        assert model.frequencies[0] == pytest.approx(freq[0], abs=FREQUENCY_TOL)
        assert np.all(model.damping == 0.02)
    # home: 213 Hz; Q2: 108 Hz (the modes move with the tool)
    assert models[0].frequencies[0] > 1.9 * models[1].frequencies[0]


def test_six_modes_hold_the_static_compliance() -> None:
    from orthoglide_pin.dynamics.inertia import inertia_table
    from orthoglide_pin.elasticity import platform_model as pm
    from orthoglide_pin.elasticity.mass import member_masses, platform_inertia

    params = og.prototype()
    point = np.array([[0.02, -0.03, 0.04]])
    table = inertia_table(params)
    carriage = float(np.mean([b.mass for b in table.kind("carriage")]))
    k, parts = pm.platform_matrices(
        point, params, member_masses(params, table), platform_inertia(params, table), carriage
    )
    w2, phi = pm.platform_modes(k, parts, point, 12)
    axes = og.design_axes(params).matrix[:, :2]
    t = (phi[0, :3, :].T @ axes).T  # (2, 12)
    full = (t / w2[0]) @ t.T
    six = tool_tip_model(params, point[0]).static_compliance()
    assert np.allclose(six, full, rtol=STATIC_TOL, atol=STATIC_TOL * np.max(np.abs(full)))


def test_tool_modes_are_added() -> None:
    tool = single_mode(2200.0, 0.03, 2e7, "x")
    model = tool_tip_model(None, (0.0, 0.0, 0.0), tool=tool)
    assert model.sources[-1] == "tool x"
    assert model.frequencies[-1] == 2200.0


def test_tool_motion_is_the_direction_scaled() -> None:
    modes = og.natural_frequencies(None, [[0.0, 0.0, 0.0], [0.03, -0.02, 0.01]])
    assert modes.tool_motion is not None and modes.tool_motion.shape == (2, 6, 3)
    size = np.linalg.norm(modes.tool_motion, axis=-1, keepdims=True)
    moving = size[..., 0] > 0.0
    unit = np.abs(modes.tool_motion / np.where(size > 0.0, size, 1.0))
    assert np.allclose(unit[moving], np.abs(modes.direction[moving]), atol=1e-12)
