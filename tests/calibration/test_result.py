"""The calibration file: full-precision round trip, and what a bad file gets."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import orthoglide_pin as og
from orthoglide_pin.calibration.identification import identify
from orthoglide_pin.calibration.measurements import Measurements
from orthoglide_pin.calibration.model import GeometricModel
from orthoglide_pin.calibration.result import Calibration, write_calibration

#: fk(ik(p)) of a loaded calibration [m].
ROUND_TRIP_TOL = 1e-12


@pytest.fixture(scope="module")
def calibration() -> Calibration:
    params = og.prototype().replace(leg_length=0.33)
    nominal = GeometricModel.nominal(params.leg_length)
    rng = np.random.default_rng(7)
    true = GeometricModel.from_vector(nominal.vector() + rng.normal(0, 1e-4, 18))
    lo = np.asarray(params.workspace.corner)
    p = rng.uniform(lo, lo + params.workspace.side, (40, 3))
    q = true.inverse_kinematics(p)
    m = p + rng.normal(0, 5e-6, p.shape)
    data = Measurements(q, m, sha256="ab" * 32)
    return Calibration.from_identification(identify(q, m, nominal), data, params)


def test_round_trip_at_full_precision(calibration: Calibration, tmp_path: Path) -> None:
    path = tmp_path / "calibration.yaml"
    write_calibration(path, calibration)
    loaded = og.load_calibration(path)
    np.testing.assert_array_equal(loaded.model.vector(), calibration.model.vector())
    np.testing.assert_array_equal(loaded.std, calibration.std)
    assert loaded.noise_estimate == calibration.noise_estimate
    assert loaded.measurements_sha256 == "ab" * 32 and loaded.poses == 40
    p = np.random.default_rng(1).uniform(-0.05, 0.05, (100, 3))
    np.testing.assert_allclose(
        loaded.direct_kinematics(loaded.inverse_kinematics(p)), p, atol=ROUND_TRIP_TOL
    )
    assert loaded.inverse_kinematics(p).shape == (100, 3)


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda d: d.update(format="other"), "format"),
        (lambda d: d.update(version=2), "version"),
        (lambda d: d["parameters"].pop("L2"), "missing L2"),
        (lambda d: d["parameters"].update(L4=0.3), "unknown L4"),
        (lambda d: d["parameters"].update(a1_x=".nan"), "parameters.a1_x"),
        (lambda d: d["std"].update(L1=-1.0), "std.L1"),
        (lambda d: d.update(noise_estimate=None), "noise_estimate"),
        (lambda d: d.update(outliers=[-1]), "outliers"),
        (lambda d: d.update(measurements=[]), "measurements"),
        (lambda d: d["parameters"].update(alpha1=1.0), "alpha"),
    ],
)
def test_bad_files_are_refused(calibration: Calibration, tmp_path: Path, edit, words: str) -> None:
    data = calibration.to_dict()
    edit(data)
    path = tmp_path / "c.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(og.InvalidParameterError) as info:
        og.load_calibration(path)
    assert words in str(info.value) and "\n" not in str(info.value)
