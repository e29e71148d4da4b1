"""The ``lobes`` command: values against the Python API, the files it writes, errors."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import run, run_json

import orthoglide_pin as og

CUT = str(og.shipped_cut_file())
SPEEDS = "4000:12000:9"


def test_json_matches_the_api(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "lobes", "0.01", "-0.02", "0", "--cut", CUT, "--speeds", SPEEDS)
    cut = og.read_cut_file(CUT)
    speeds = np.linspace(4000.0, 12000.0, 9) * 2.0 * math.pi / 60.0
    lobes = og.stability_lobes(cut, [0.01, -0.02, 0.0], speeds=speeds)
    np.testing.assert_allclose(data["limit_depth_mm"], lobes.depths * 1e3, rtol=1e-12)
    assert data["speeds_rpm"] == pytest.approx(np.linspace(4000.0, 12000.0, 9).tolist())
    assert data["spindle_speed_rpm"] == pytest.approx(12000.0)
    assert data["margin"] == pytest.approx(lobes.depths[-1] / 0.002, rel=1e-9)
    assert data["files"] == [] and data["milling"] == "down"
    assert [m["source"] for m in data["modes"]][-2:] == ["tool x", "tool y"]


def test_text_and_files(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "lobes"
    status, text, err = run(
        capsys, "lobes", "0", "0", "0", "--cut", CUT, "--speeds", SPEEDS, "--out", str(out)
    )
    assert status == 0 and err == ""
    assert "lowest limit" in text and "margin" in text and str(out) in text
    payload = json.loads((out / "lobes.json").read_text())
    rows = (out / "lobes.csv").read_text().splitlines()
    assert rows[0] == "speed_rpm,limit_depth_mm,zero_order_depth_mm" and len(rows) == 10
    assert float(rows[1].split(",")[1]) == pytest.approx(payload["limit_depth_mm"][0], rel=1e-5)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--speeds", "1:2"), "--speeds"),
        (("--feed-angle", "north"), "--feed-angle"),
        (("--model", "beam"), "invalid choice"),
    ],
)
def test_bad_options_give_one_line(
    capsys: pytest.CaptureFixture[str], args: tuple[str, ...], message: str
) -> None:
    status, out, err = run(capsys, "lobes", "0", "0", "0", "--cut", CUT, *args)
    assert status == 2 and out == ""
    assert message in err and len(err.strip().splitlines()) == 1


def test_bad_cut_file_writes_nothing(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    bad = tmp_path / "cut.yaml"
    bad.write_text("tool: {diameter: 10, teeth: 3}\n")
    status, out, err = run(
        capsys, "lobes", "0", "0", "0", "--cut", str(bad), "--out", str(tmp_path / "o")
    )
    assert status == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_json_keys_and_files_are_documented(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    from test_docs_pages import documented_keys

    out = tmp_path / "l"
    data = run_json(
        capsys, "lobes", "0", "0", "0", "--cut", CUT, "--speeds", SPEEDS, "--out", str(out)
    )
    assert set(data) == documented_keys("lobes")
    assert data["files"] == ["lobes.json", "lobes.csv"]
    header = (out / "lobes.csv").read_text().splitlines()[0]
    assert (
        f"`{header}`"
        in Path(__file__).parents[2].joinpath("docs/reference/formats.md").read_text()
    )
