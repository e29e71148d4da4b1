"""Strict JSON everywhere: never NaN or Infinity, in ``--json`` output or in the files."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import run

from orthoglide_pin._io import json_text, strict_json
from orthoglide_pin.cli import _common as common
from orthoglide_pin.exceptions import NonFiniteResultError
from orthoglide_pin.sweep import runner

#: Exit status of every error.
ERROR = 2


def strict_loads(text: str) -> Any:
    """``json.loads`` that refuses ``NaN``, ``Infinity`` and ``-Infinity``."""

    def refuse(name: str) -> Any:
        raise ValueError(f"not JSON: {name}")

    return json.loads(text, parse_constant=refuse)


# ------------------------------------------------------------ output check
@pytest.mark.parametrize(
    ("payload", "where"),
    [
        ({"p": [0.1, math.nan, 0.0]}, "p[1]"),
        ({"J_inv": np.array([[1.0, 2.0], [3.0, np.inf]])}, "J_inv[1][1]"),
        ({"a": {"b": [{"c": -math.inf}]}}, "a.b[0].c"),
        ({"x": np.float64("nan")}, "x"),
    ],
)
def test_a_non_finite_result_is_refused(
    capsys: pytest.CaptureFixture[str], payload: dict[str, Any], where: str
) -> None:
    for as_json in (True, False):  # text output is checked as well
        with pytest.raises(NonFiniteResultError) as info:
            common.emit(argparse.Namespace(json=as_json), payload, "text")
        assert info.value.where == where
        assert capsys.readouterr().out == ""  # nothing printed


def test_numpy_results_print_as_strict_json(capsys: pytest.CaptureFixture[str]) -> None:
    payload = {
        "n": np.int64(3),
        "v": np.arange(3.0),
        "ok": np.bool_(True),
        "none": None,
        "path": Path("out") / "r.json",
    }
    common.emit(argparse.Namespace(json=True), payload, "")
    assert strict_loads(capsys.readouterr().out) == {
        "n": 3,
        "v": [0.0, 1.0, 2.0],
        "ok": True,
        "none": None,
        "path": "out/r.json",
    }


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_command_with_a_non_finite_result_exits_2(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, bad: float
) -> None:
    import orthoglide_pin.kinematics.closed_form as closed_form

    monkeypatch.setattr(
        closed_form, "direct_kinematics", lambda *_, **__: np.array([0.01, bad, 0.0])
    )
    code, out, err = run(capsys, "fk", "0", "0", "0", "--json")
    assert (code, out) == (ERROR, "")
    assert err.count("\n") == 1 and err.startswith("orthoglide fk: error: the result p[1] is ")


@pytest.mark.parametrize(
    "argv",
    [
        ["ik", "0.1", "-0.07", "0.1"],
        ["fk", "-0.07", "0.18", "0.0"],
        ["fk", "0.05", "0.05", "0.05", "--all-branches"],
        ["jacobian", "0.178", "0.179", "0.179"],  # near the parallel singularity
        ["indices", "0.178", "0.179", "0.179"],
        ["indices", "-0.0730", "-0.0730", "-0.0730"],
        ["design", "--workspace", "0.2", "--psi", "0.999", "1.001", "--grid", "3"],
        [
            "dynamics",
            "--point",
            "0.1,0.1,0.1",
            "--velocity",
            "100,0,0",
            "--acceleration",
            "0,1e4,0",
        ],
    ],
)
def test_extreme_but_valid_inputs_give_strict_json(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    code, out, err = run(capsys, *argv, "--json")
    if code == ERROR:  # refused is fine, as one line and no output
        assert out == "" and err.count("\n") == 1, err
        return
    assert code == 0, err
    strict_loads(out)


# ------------------------------------------------------------ files
def test_strict_json_maps_non_finite_numbers_to_null() -> None:
    value = {"a": [1.5, math.nan], "b": np.array([np.inf, -np.inf]), 3: np.float32(2.0)}
    assert strict_json(value) == {"a": [1.5, None], "b": [None, None], "3": 2.0}
    assert strict_loads(json_text(value)) == {"a": [1.5, None], "b": [None, None], "3": 2.0}
    with pytest.raises(ValueError):
        json.dumps({"a": math.nan}, allow_nan=False)  # what json_text avoids


def test_sweep_parts_are_strict_json_and_read_back_as_nan(tmp_path: Path) -> None:
    from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec, design_key

    design = SweepSpec(axes=(SweepAxis("leg_length", (0.3,)),)).designs()[0]
    key = design_key(design)
    row = {
        "key": key,
        "status": "invalid",
        "error": "too short",
        "mode": design["mode"],
        "leg_length": 0.3,
        "stroke": math.nan,
    }
    path = runner.write_part(tmp_path, row)
    text = path.read_text()
    assert "NaN" not in text
    assert strict_loads(text)["stroke"] is None
    back = runner.load_parts(tmp_path, [design])[key]
    assert back["stroke"] is None and back["leg_length"] == 0.3
