"""A planned trajectory in the viewer: trajectory.csv read, checked, played, coloured by feed."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.cli import main
from orthoglide_pin.exceptions import MissingExtraError
from orthoglide_pin.machine.digest import design_comment
from orthoglide_pin.viewer import Viewer
from orthoglide_pin.viewer.planned import FEED_COLORMAP, REQUIRED_COLUMNS, read_trajectory
from orthoglide_pin.viewer.visualizer import MAX_PATH_POINTS

pytest.importorskip("toppra")

#: A line then a corner at 100 mm/s: the feed runs from rest to 0.1 m/s and back.
PROGRAM = "G21 G90 G64 P0.05\nG1 X30 F6000\nG1 Y30\nM2\n"
FEED = 0.1
#: Colours travel as float32.
FLOAT32_TOL = 1e-6
#: The file's values are written to 10 significant digits.
FILE_RTOL = 1e-9
#: ... and a value near zero to this absolute precision [m, s, m/s].
FILE_ATOL = 1e-15


@pytest.fixture(scope="module")
def planned(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("plan")
    prog = folder / "part.nc"
    prog.write_text(PROGRAM)
    out = folder / "plan"
    argv = ["plan", str(prog), "--max-slider-speed", "1", "--max-slider-acceleration", "10"]
    assert main([*argv, "--dt", "0.005", "--out", str(out)]) == 0
    return out / "trajectory.csv"


def _path_colors(viewer: Viewer) -> np.ndarray:
    for c in viewer.scene.commands():
        if c["type"] == "set_object" and c["path"].endswith("/path"):
            attrs = c["object"]["geometries"][0]["data"]["attributes"]
            assert c["object"]["materials"][0]["vertexColors"] == 2  # three.js VertexColors
            raw = attrs["color"]["array"]
            return np.frombuffer(getattr(raw, "data", raw), dtype=np.float32).reshape(-1, 3)
    raise AssertionError("no path drawn")


def test_the_path_is_coloured_by_feed(planned: Path) -> None:
    params = og.prototype()
    traj = read_trajectory(planned, params)
    rows = np.loadtxt(planned, delimiter=",", skiprows=2)  # the design, the header
    np.testing.assert_allclose(traj.t, rows[:, 0], rtol=FILE_RTOL)
    assert traj.path_speed.max() == pytest.approx(FEED, rel=1e-3)  # the programmed feed
    viewer = Viewer(og.ClosedLoopModel(params))
    frames = viewer.play(traj, follow=None)
    assert frames.times[-1] == pytest.approx(traj.t[-1], rel=1e-2)
    rgb = _path_colors(viewer)
    assert rgb.shape == (traj.t.size, 3)
    cmap = matplotlib.colormaps[FEED_COLORMAP]
    expected = cmap(traj.path_speed / traj.path_speed.max())[:, :3]
    np.testing.assert_allclose(rgb, expected, atol=FLOAT32_TOL)
    np.testing.assert_allclose(rgb[0], cmap(0.0)[:3], atol=FLOAT32_TOL)  # at rest
    legend = viewer.scene.legend
    assert legend is not None
    labels = [item["label"] for item in legend["items"]]
    top = f"feed {6e4 * traj.path_speed.max():.0f} mm/min"  # the feed in mm/min, as F
    assert "feed 0 mm/min" in labels and top in labels and "tool path" not in labels
    assert top == "feed 6000 mm/min"


def test_the_legend_ends_at_the_largest_feed_of_a_decimated_path() -> None:
    viewer = Viewer(og.ClosedLoopModel(og.prototype()))
    n = 3 * MAX_PATH_POINTS + 1
    p = np.zeros((n, 3))
    p[:, 0] = np.linspace(-0.05, 0.05, n)
    speed = np.full(n, 0.01)
    speed[1] = 0.04  # a peak the decimated path does not draw
    viewer.add_path(p, speed)
    legend = viewer.scene.legend
    assert legend is not None
    feeds = [item["label"] for item in legend["items"] if item["label"].startswith("feed ")]
    assert feeds[0] == "feed 0 mm/min" and feeds[-1] == "feed 2400 mm/min"
    cmap = matplotlib.colormaps[FEED_COLORMAP]
    np.testing.assert_allclose(_path_colors(viewer)[1], cmap(0.25)[:3], atol=FLOAT32_TOL)


def test_the_view_terminal_the_legend_and_the_plan_page_agree_on_the_feed(
    planned: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "view.html"
    assert main(["view", "--trajectory", str(planned), "--static", str(target)]) == 0
    text = capsys.readouterr().out
    found = re.search(r"path coloured by feed, 0 to (\d+) mm/min", text)
    assert found is not None
    top = f"feed {found.group(1)} mm/min"
    assert f'"{top}"' in target.read_text()  # the legend's last swatch
    page = (planned.parent / "plan.html").read_text()
    assert f"peak {top}" in page


def test_view_command_plays_a_planned_trajectory(
    planned: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "view.html"
    argv = ["view", "--json", "--trajectory", str(planned), "--static", str(target)]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["frames"] > 10 and payload["max_path_speed"] == pytest.approx(FEED, rel=1e-3)
    assert target.stat().st_size > 100_000


@pytest.fixture(scope="module")
def planned_parquet(planned: Path) -> Path:
    """The same plan as ``planned``, written as Parquet."""
    pytest.importorskip("pyarrow.parquet")
    prog = planned.parent.parent / "part.nc"
    out = planned.parent.parent / "plan-parquet"
    argv = ["plan", str(prog), "--max-slider-speed", "1", "--max-slider-acceleration", "10"]
    argv += ["--dt", "0.005", "--out", str(out), "--trajectory-format", "parquet"]
    assert main(argv) == 0
    return out / "trajectory.parquet"


def test_a_parquet_trajectory_reads_as_the_csv_of_the_same_plan(
    planned: Path, planned_parquet: Path
) -> None:
    csv, parquet = read_trajectory(planned), read_trajectory(planned_parquet)
    assert parquet.t.shape == csv.t.shape and parquet.p.shape == csv.p.shape
    for a, b in ((parquet.t, csv.t), (parquet.p, csv.p), (parquet.path_speed, csv.path_speed)):
        assert a.dtype == np.float64
        np.testing.assert_allclose(a, b, rtol=FILE_RTOL, atol=FILE_ATOL)


def test_a_parquet_trajectory_decodes_only_the_columns_the_viewer_needs(
    planned_parquet: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    assert len(pq.read_schema(planned_parquet).names) > len(REQUIRED_COLUMNS)
    asked: list[object] = []
    read = pq.ParquetFile.read

    def spy(self: object, columns: object = None, **kwargs: object) -> object:
        asked.append(columns)
        return read(self, columns=columns, **kwargs)

    monkeypatch.setattr(pq.ParquetFile, "read", spy)
    read_trajectory(planned_parquet)
    assert asked == [list(REQUIRED_COLUMNS)]


def test_view_plays_a_parquet_trajectory(
    planned_parquet: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "view.html"
    argv = ["view", "--json", "--trajectory", str(planned_parquet), "--static", str(target)]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["frames"] > 10 and payload["max_path_speed"] == pytest.approx(FEED, rel=1e-3)


def test_a_parquet_trajectory_without_pyarrow_names_the_extra(
    planned_parquet: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow fails
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", None)
    with pytest.raises(MissingExtraError, match=re.escape("orthoglide-pin[tables]")):
        read_trajectory(planned_parquet)
    argv = ["view", "--trajectory", str(planned_parquet), "--static", "unused.html"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "orthoglide-pin[tables]" in err


def _csv(rows: list[str], params: og.OrthoglideParams | None = None) -> str:
    return design_comment(params) + "\n".join(rows) + "\n"


GOOD = ["t,x,y,z,path_speed", "0,0,0,0,0", "0.1,0.001,0,0,0.02", "0.2,0.002,0,0,0"]


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("", "empty"),
        (design_comment(), "empty"),
        (_csv(["t,x,y,path_speed", "0,0,0,0", "1,0,0,0"]), "no z"),
        (_csv(["t,x,y,z,path_speed,w", "0,0,0,0,0,1", "1,0,0,0,0,1"]), "column 'w'"),
        (_csv(["t,x,y,z,t", "0,0,0,0,0"]), "column 't' twice"),
        (_csv([*GOOD[:2], "0.1,0,0"]), "row 2"),
        (_csv([*GOOD[:2], "0.1,0,zero,0,0"]), "row 2: 'zero'"),
        (_csv([*GOOD[:2], "0.1,0,nan,0,0"]), "row 2, y = nan"),
        (_csv([*GOOD[:2], "0.1,0,inf,0,0"]), "row 2, y = inf"),
        (_csv(GOOD[:2]), "1 rows"),
        (_csv([*GOOD[:3], "0.1,0.002,0,0,0"]), "row 3, t = 0.1"),
        (_csv([*GOOD[:2], "0.1,0,0,0,-0.5"]), "row 2, path_speed < 0"),
        (_csv([*GOOD[:2], "0.1,0.3,0,0,0"]), "row 2, point (300.000, 0.000, 0.000) mm"),
    ],
)
def test_a_bad_trajectory_is_one_line(
    text: str, says: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = tmp_path / "trajectory.csv"
    bad.write_text(text)
    target = tmp_path / "x.html"
    assert main(["view", "--trajectory", str(bad), "--static", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "trajectory file" in err, err
    assert not target.exists()


def test_the_good_file_and_other_bad_arguments(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    good = tmp_path / "trajectory.csv"
    good.write_text(_csv(GOOD))
    traj = read_trajectory(good, og.prototype())
    np.testing.assert_array_equal(traj.path_speed, [0.0, 0.02, 0.0])
    # the file is judged against the machine's cube: another cube holds this point
    far = tmp_path / "far.csv"
    far.write_text(_csv([*GOOD[:2], "0.1,0.14,0.1,0.1,0"]))
    with pytest.raises(og.InvalidParameterError, match="row 2"):
        read_trajectory(far, None)  # the prototype
    other = og.prototype().replace(workspace_corner=(0.0, 0.0, 0.0), workspace_side=0.15)
    far.write_text(_csv([*GOOD[:2], "0.1,0.14,0.1,0.1,0"], other))
    assert read_trajectory(far, other).p[1, 0] == 0.14
    for argv, says in (
        (["--trajectory", "spiral"], "FILE.csv"),
        (["--trajectory", str(tmp_path / "none.csv")], "trajectory file"),
    ):
        assert main(["view", *argv, "--static", str(tmp_path / "y.html")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and says in err
    assert not (tmp_path / "y.html").exists()
