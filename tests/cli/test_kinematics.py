"""``orthoglide urdf -o``: the URDF and its loop data, written together."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import run, run_json

import orthoglide_pin as og


def test_urdf_output_writes_the_loops_beside_it(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    target = tmp_path / "out" / "orthoglide.urdf"
    data = run_json(capsys, "urdf", "-o", str(target), "--param", "leg_length=0.33")
    loops = tmp_path / "out" / "orthoglide.loops.yaml"
    assert Path(data["path"]).samefile(target) and Path(data["loops"]).samefile(loops)
    assert sorted(p.name for p in target.parent.iterdir()) == [loops.name, target.name]
    spec = og.read_loops(loops)
    model = pin.buildModelFromUrdf(str(target))
    for closure in spec.closures:
        assert model.existFrame(closure.frame1) and model.existFrame(closure.frame2)
    code, out, err = run(capsys, "urdf", "-o", str(target))
    assert (code, err) == (0, "")
    assert out.split() == [str(target.resolve()), str(loops.resolve())]


def test_urdf_output_leaves_a_foreign_file_alone(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    (tmp_path / "m.loops.yaml").write_text("mine\n")
    code, out, err = run(capsys, "urdf", "-o", str(tmp_path / "m.urdf"))
    assert (code, out) == (2, "")
    assert err.startswith("orthoglide") and "left alone" in err and err.count("\n") == 1
    assert (tmp_path / "m.loops.yaml").read_text() == "mine\n"
    assert not (tmp_path / "m.urdf").exists()


def test_rewriting_the_shipped_urdf_keeps_its_mode(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """As ``make urdf`` does on the tracked file, under a strict umask."""
    target = tmp_path / "orthoglide_prototype.urdf"
    target.write_text("old")
    target.chmod(0o644)
    old = os.umask(0o077)
    try:
        assert run(capsys, "urdf", "-o", str(target))[0] == 0
    finally:
        os.umask(old)
    assert target.stat().st_mode & 0o777 == 0o644
    assert target.read_text() == og.render_urdf()
    assert (tmp_path / "orthoglide_prototype.loops.yaml").stat().st_mode & 0o777 == 0o600


def test_written_files_are_readable_by_others(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Under the usual umask 022, as any other tool's output: 0644 files."""
    old = os.umask(0o022)
    try:
        assert run(capsys, "urdf", "-o", str(tmp_path / "m.urdf"))[0] == 0
    finally:
        os.umask(old)
    for name in ("m.urdf", "m.loops.yaml"):
        assert (tmp_path / name).stat().st_mode & 0o777 == 0o644


@pytest.mark.parametrize("method", ["closed-form", "pinocchio"])
def test_jacobian_refuses_a_point_beyond_the_slider_limits(
    capsys: pytest.CaptureFixture[str], method: str
) -> None:
    params = og.prototype()
    upper = f"{params.slider_upper:.6g}"
    # reachable, regular, but slider 1 at 0.19 m > the upper limit (as ik refuses it)
    code, out, err = run(capsys, "jacobian", "0.19", "0", "0", "--method", method)
    assert (code, out) == (2, "") and err.count("\n") == 1
    assert "outside the limits" in err and upper in err and "check_limits" not in err
    # Q2, on the derived limits, is inside; J there agrees with the API's
    q2 = params.workspace.q1 + params.workspace.side
    data = run_json(capsys, "jacobian", *(repr(float(v)) for v in q2), "--method", method)
    np.testing.assert_allclose(data["J"], og.jacobian(q2, params), rtol=0, atol=1e-9)
