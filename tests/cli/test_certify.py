"""The ``certify`` command, and the certification reported by ``design``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CUBE_CORNER, lapack_factors, run, run_json

import orthoglide_pin as og

#: The paper's design: leg 310.58 mm for a 200 mm cube and [0.5, 2].
PAPER = og.design_from_workspace(0.2, 0.5, 2.0, grid_points=2)
#: The keys every ``certify --json`` object starts with (the documented contract).
KEYS = ("certified", "factor_bounds", "counterexample", "boxes", "seconds")
ERROR = 2
#: Exit statuses of ``certify``: certified, violated, undecided.
CERTIFIED, VIOLATED, UNDECIDED = 0, 1, 3
#: The prototype's factors over its 200 mm cube, to four decimals (computed:
#: ``og.certify(og.prototype()).attained``; the paper rounded 310.58 mm to 310 mm).
PROTOTYPE_FACTORS = (0.4989, 2.0090)


def _certify_json(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any]]:
    code, out, err = run(capsys, "certify", *argv, "--json")
    assert err == "" and code in (CERTIFIED, VIOLATED, UNDECIDED), err
    data = json.loads(out)
    assert data["exit_status"] == code
    return code, data


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
    code, data = _certify_json(capsys, "--workspace", "0.21", *_corner(CUBE_CORNER))
    assert code == VIOLATED
    assert data["certified"] is False and data["status"] == "violated"
    p = np.array(data["counterexample"])
    factors = lapack_factors(p, 0.31)  # the prototype's 310 mm leg, another route
    assert factors[0] < 0.5 or factors[2] > 2.0
    assert np.all(p >= CUBE_CORNER) and np.all(p <= CUBE_CORNER + 0.21)
    code, text, _ = run(capsys, "certify", "--workspace", "0.21", *_corner(CUBE_CORNER))
    assert code == VIOLATED and "VIOLATED" in text and "counterexample" in text
    assert "note:" not in text  # another cube than the prototype's


def test_infinite_bounds_print_as_null(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys,
        *("certify", "--workspace", "0.0121", "--corner", "0", "0.2", "0.2"),
        *("--param", "leg_length=0.3", "--psi", "1e-6", "1e6", "--max-boxes", "50", "--json"),
    )
    assert code == UNDECIDED  # neither proven nor refuted
    data = json.loads(out)  # strict: no Infinity
    assert data["status"] == "singular" and data["exit_status"] == UNDECIDED
    assert data["certified"] is False and data["factor_bounds"][1] is None


@pytest.mark.parametrize(
    ("argv", "mentions"),
    [
        (("--psi", "2", "0.5"), "psi_min"),
        (("--psi", "1e-12", "1e12"), "psi_max=1000000000000.0: expected a value in [1, 1e+06]"),
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
    assert len(err.strip().splitlines()) == 1 and err.startswith("orthoglide certify: error:")
    assert mentions in err


def test_design_reports_its_certification(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "11")
    assert data["certified"] is True
    cert = data["certification"]
    lo, hi = cert["factor_bounds"]
    tol = cert["tolerance"]
    # measured to the bounds widened by the tolerance (Q1 and Q2 reach the bounds)
    assert data["certified_margin"] == pytest.approx(min(lo - (0.5 - tol), 2.0 + tol - hi))
    assert 0.0 <= data["certified_margin"] <= tol
    assert data["criterion"] == {"psi_min": 0.5, "psi_max": 2.0, "tolerance": tol}
    skipped = run_json(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--no-certify")
    assert skipped["certified"] is None and skipped["certification"] is None
    text = run(capsys, "design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "11")[1]
    assert "certified      yes" in text


def test_certify_proves_what_design_proved(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    config = tmp_path / "d.yaml"
    argv = ("design", "--workspace", "0.25", "--psi", "0.4", "2.5", "--grid", "5")
    designed = run_json(capsys, *argv, "--write-config", str(config))
    assert designed["certified"] is True
    assert og.OrthoglideParams.load(config).psi_min == 0.4  # the file carries the criterion
    code, data = _certify_json(capsys, "--config", str(config))
    assert code == CERTIFIED and data["certified"] is True and data["status"] == "certified"
    assert data["criterion"] == {
        "psi_min": 0.4,
        "psi_max": 2.5,
        "tolerance": 1e-4,
        "from": "machine",
    }
    # the same proof: the same enclosure, the same margin
    assert data["factor_bounds"] == designed["certification"]["factor_bounds"]
    assert data["margin"] == designed["certified_margin"] >= 0.0
    code, text, _ = run(capsys, "certify", "--config", str(config))
    assert code == CERTIFIED and "CERTIFIED" in text and "[0.4, 2.5]" in text
    # --psi overrides the file's criterion, and says so
    code, data = _certify_json(capsys, "--config", str(config), "--psi", "0.5", "2")
    assert code == VIOLATED and data["criterion"]["from"] == "--psi"


def test_the_exit_status_follows_the_verdict(capsys: pytest.CaptureFixture[str]) -> None:
    assert _certify_json(capsys)[0] == VIOLATED  # the prototype: [0.4989, 2.0090]
    assert _certify_json(capsys, "--psi", "0.45", "2.1")[0] == CERTIFIED
    leg = f"leg_length={PAPER.leg_length!r}"
    argv = ("--workspace", "0.2", *_corner(PAPER.cube_corner[0]), "--param", leg)
    # the design's own cube at a tolerance finer than the boxes can resolve
    code, data = _certify_json(capsys, *argv, "--psi", "0.5", "2", "--tol", "1e-12")
    assert code == UNDECIDED and data["status"] == "undecided"
    assert data["counterexample"] is None and data["margin"] < 0.0
    help_text = run(capsys, "certify", "--help")[1]
    for words in ("0 when certified", "1 when violated", "3 when undecided", "2 on an error"):
        assert words in " ".join(help_text.split())


def test_an_unreachable_tolerance_never_turns_a_proof_into_undecided(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, data = _certify_json(capsys, "--psi", "0.4", "2.5", "--tol", "1e-8")
    assert code == CERTIFIED and data["status"] == "certified" and data["certified"] is True
    assert data["margin"] > 0.09 and data["tight"] is False
    code, text, _ = run(capsys, "certify", "--psi", "0.4", "2.5", "--tol", "1e-8")
    assert code == CERTIFIED and "CERTIFIED" in text and "not within 1e-08" in text


def test_the_prototype_is_told_as_it_is(capsys: pytest.CaptureFixture[str]) -> None:
    code, data = _certify_json(capsys)
    assert code == VIOLATED
    assert data["criterion"] == {
        "psi_min": 0.5,
        "psi_max": 2.0,
        "tolerance": 1e-4,
        "from": "machine",
    }
    lo, hi = data["attained"]
    assert (round(lo, 4), round(hi, 4)) == PROTOTYPE_FACTORS
    # another route: LAPACK at the corner Q2 of the cube, where both extremes are
    q2 = np.full(3, CUBE_CORNER + 0.2)
    f = lapack_factors(q2, 0.31)
    assert (round(float(f[0]), 4), round(float(f[2]), 4)) == PROTOTYPE_FACTORS
    assert "310.58 mm" in data["note"]
    text = run(capsys, "certify")[1]
    assert "note: the prototype's 310 mm legs are the paper's rounding of the 310.58 mm" in text
    assert f"[{PROTOTYPE_FACTORS[0]:.4f}, {PROTOTYPE_FACTORS[1]:.4f}]" in text
