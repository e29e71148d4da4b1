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


# ------------------------------------------------------------------ --map
#: Relative agreement of the map's worst limit with the lobes there: both are
#: found to the search's tolerance (``stability_sd.TOLERANCE``, 0.3 %) from
#: different first brackets (the lobes start from the zero-order solution).
MAP_VS_LOBES_RTOL = 2 * 3e-3
#: The map at N = 3 and the designs it is tested on.
MAP_GRID = "3"
DESIGNS = [(), ("--param", "leg_length=0.34075")]


def _params(design: tuple[str, ...]) -> og.OrthoglideParams:
    p = og.prototype()
    return p.replace(leg_length=float(design[1].split("=")[1])) if design else p


@pytest.mark.parametrize("design", DESIGNS, ids=["prototype", "leg_340.75mm"])
def test_map_matches_the_api_and_the_lobes_at_its_worst_point(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, design: tuple[str, ...]
) -> None:
    out = tmp_path / "map"
    data = run_json(
        capsys, "lobes", "--map", "--cut", CUT, "--grid", MAP_GRID, *design, "--out", str(out)
    )
    params, cut = _params(design), og.read_cut_file(CUT)
    points = np.array(data["points"])
    assert points.shape == (27, 3)
    np.testing.assert_allclose(points.min(axis=0), params.workspace.q1, atol=1e-12)
    np.testing.assert_allclose(points.max(axis=0), params.workspace.q2, atol=1e-12)
    expected = og.limit_depth_map(cut, points, params=params)
    np.testing.assert_allclose(data["limit"], expected, rtol=1e-12)  # all finite here
    worst = int(np.argmin(expected))
    assert data["lowest"]["point"] == data["points"][worst]
    assert data["lowest"]["margin"] == pytest.approx(expected[worst] / 0.002, rel=1e-12)
    assert data["design"] == og.design_digest(params)
    speed = cut.spindle_speed
    assert speed is not None and data["spindle_speed_rpm"] == pytest.approx(12000.0)
    lobes = og.stability_lobes(cut, points[worst], params=params, speeds=[speed])
    assert data["lowest"]["limit"] == pytest.approx(lobes.limit_at(speed), rel=MAP_VS_LOBES_RTOL)
    modes = og.natural_frequencies(params, points, count=1).lowest
    np.testing.assert_allclose(data["lowest_mode"], modes, rtol=1e-12)
    assert json.loads((out / "lobes_map.json").read_text()) == data
    rows = (out / "lobes_map.csv").read_text().splitlines()
    assert rows[0] == "x_m,y_m,z_m,limit_m,margin,lowest_mode_hz" and len(rows) == 28
    cells = np.array([[float(c) for c in r.split(",")] for r in rows[1:]])
    np.testing.assert_allclose(cells[:, :3], points, atol=1e-9)
    np.testing.assert_allclose(cells[:, 3], expected, rtol=1e-8)


def test_map_at_another_speed_and_in_text(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(capsys, "lobes", "--map", "--cut", CUT, "--grid", "2", "--speed", "9000")
    cut = og.read_cut_file(CUT)
    expected = og.limit_depth_map(cut, data["points"], speed=9000.0 * 2.0 * math.pi / 60.0)
    np.testing.assert_allclose(data["limit"], expected, rtol=1e-12)
    status, text, err = run(capsys, "lobes", "--map", "--cut", CUT, "--grid", "2")
    assert status == 0 and err == ""
    assert "lowest limit" in text and "highest limit" in text and "margin of the 2 mm" in text


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--map", "0", "0", "0"), "no point with --map"),
        (("0", "0"), "X Y Z"),
        (("0", "0", "0", "--grid", "3"), "--grid"),
        (("0", "0", "0", "--speed", "9000"), "--speed"),
        (("--map", "--speeds", "1000:2000:3"), "--speeds"),
        (("--map", "--grid", "1"), "--grid"),
        (("--map", "--grid", "12"), "--grid"),
        (("--map", "--grid", "three"), "--grid"),
        (("--map", "--speed", "nan"), "--speed"),
        (("--map", "--speed", "0"), "--speed"),
        (("--map", "--feed-angle", "north"), "--feed-angle"),
    ],
)
def test_map_bad_options_give_one_line(
    capsys: pytest.CaptureFixture[str], args: tuple[str, ...], message: str
) -> None:
    status, out, err = run(capsys, "lobes", "--cut", CUT, *args)
    assert status == 2 and out == ""
    assert message in err and len(err.strip().splitlines()) == 1


def test_map_without_a_speed_is_refused(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    cut = tmp_path / "cut.yaml"
    text = Path(CUT).read_text()
    cut.write_text(text.replace("spindle_speed: 12000", "spindle_speed: program"))
    assert "program" in cut.read_text()
    status, out, err = run(capsys, "lobes", "--map", "--cut", str(cut), "--grid", "2")
    assert status == 2 and out == "" and "--speed" in err


def test_map_never_overwrites_a_users_directory(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep")
    status, _, err = run(capsys, "lobes", "--map", "--cut", CUT, "--grid", "2", "--out", str(out))
    assert status == 2 and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]
    status, _, _ = run(
        capsys, "lobes", "--map", "--cut", CUT, "--grid", "2", "--out", str(out), "--force"
    )
    assert status == 0 and (out / "notes.txt").read_text() == "keep"
    assert (out / "lobes_map.csv").is_file()


def test_map_json_keys_are_documented(capsys: pytest.CaptureFixture[str]) -> None:
    from test_docs_pages import documented_keys

    data = run_json(capsys, "lobes", "--map", "--cut", CUT, "--grid", "2")
    assert set(data) == documented_keys("lobes --map")
    header = "x_m,y_m,z_m,limit_m,margin,lowest_mode_hz"
    formats = Path(__file__).parents[2].joinpath("docs/reference/formats.md").read_text()
    assert f"`{header}`" in formats
