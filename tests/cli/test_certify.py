"""The ``certify`` command, and the certification reported by ``design``."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import CUBE_CORNER, lapack_factors, run, run_json

import orthoglide_pin as og

#: The paper's design: leg 310.58 mm for a 200 mm cube and [0.5, 2].
PAPER = og.design_from_workspace(0.2, 0.5, 2.0, grid_points=2)
#: The keys every ``certify --json`` object starts with (the documented contract).
KEYS = ("certified", "factor_bounds", "counterexample", "boxes", "seconds")
ERROR = 2


def _corner(value: float) -> list[str]:
    return ["--corner", *(repr(float(value)),) * 3]


def test_the_paper_design_is_certified(capsys: pytest.CaptureFixture[str]) -> None:
    leg = f"leg_length={PAPER.leg_length!r}"
    argv = ["certify", "--workspace", "0.2", *_corner(PAPER.cube_corner[0]), "--param", leg]
    data = run_json(capsys, *argv, "--psi", "0.499", "2.001")
    assert tuple(data)[: len(KEYS)] == KEYS
    assert data["certified"] is True and data["counterexample"] is None
    lo, hi = data["factor_bounds"]
    assert 0.499 <= lo <= 0.5 <= 2.0 <= hi <= 2.001
    assert data["boxes"] > 8 and data["seconds"] > 0.0
    expected = og.certify_cube(PAPER.leg_length, PAPER.cube_corner, 0.2, 0.499, 2.001)
    assert data["factor_bounds"] == list(expected.factor_bounds)
    code, out, _ = run(capsys, *argv, "--psi", "0.499", "2.001")
    assert code == 0 and "CERTIFIED" in out and "certified enclosure" in out


def test_a_210_mm_cube_gives_a_counterexample(capsys: pytest.CaptureFixture[str]) -> None:
    # negative corner coordinates parse as values, not options
    data = run_json(capsys, "certify", "--workspace", "0.21", *_corner(CUBE_CORNER))
    assert data["certified"] is False and data["status"] == "violated"
    p = np.array(data["counterexample"])
    factors = lapack_factors(p, 0.31)  # the prototype's 310 mm leg, another route
    assert factors[0] < 0.5 or factors[2] > 2.0
    assert np.all(p >= CUBE_CORNER) and np.all(p <= CUBE_CORNER + 0.21)
    text = run(capsys, "certify", "--workspace", "0.21", *_corner(CUBE_CORNER))[1]
    assert "VIOLATED" in text and "counterexample" in text


def test_infinite_bounds_print_as_null(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys,
        *("certify", "--workspace", "0.0121", "--corner", "0", "0.2", "0.2"),
        *("--param", "leg_length=0.3", "--psi", "1e-12", "1e12", "--max-boxes", "50", "--json"),
    )
    assert code == 0
    data = json.loads(out)  # strict: no Infinity
    assert data["certified"] is False and data["factor_bounds"][1] is None


@pytest.mark.parametrize(
    ("argv", "mentions"),
    [
        (("--psi", "2", "0.5"), "psi_min"),
        (("--workspace", "-0.1"), "side"),
        (("--corner", "0", "x", "0"), "--corner Y"),
        (("--tol", "nan"), "--tol"),
        (("--max-boxes", "0"), "--max-boxes"),
    ],
)
def test_bad_arguments_are_one_line(
    capsys: pytest.CaptureFixture[str], argv: tuple[str, ...], mentions: str
) -> None:
    code, out, err = run(capsys, "certify", *argv)
    assert code == ERROR and out == ""
    assert len(err.strip().splitlines()) == 1 and err.startswith("orthoglide: error:")
    assert mentions in err


def test_design_reports_its_certification(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "11")
    assert data["certified"] is True
    cert = data["certification"]
    lo, hi = cert["factor_bounds"]
    assert data["certified_margin"] == pytest.approx(min(lo - 0.5, 2.0 - hi))
    assert -cert["tolerance"] <= data["certified_margin"] <= 0.0  # Q1, Q2 reach the bounds
    skipped = run_json(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--no-certify")
    assert skipped["certified"] is None and skipped["certification"] is None
    text = run(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "11")[1]
    assert "certified      yes" in text
