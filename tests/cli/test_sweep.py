"""The ``sweep`` command, in-process through ``main``."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
from conftest import PROTOTYPE_LEG, run, run_json

import orthoglide_pin as og
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec

#: Exit status of every error.
ERROR = 2
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
GRID = "12"
#: The paper's prototype (section 4): stroke 257 mm for the designed 310.6 mm leg.
PAPER_STROKE = 0.2570
PAPER_LENGTH_TOL = 5e-5


def _sweep(out: Path, *extra: str) -> list[str]:
    return ["sweep", "--grid", GRID, "--workers", "1", "--out", str(out), *extra]


def test_leg_length_sweep(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    data = run_json(capsys, *_sweep(tmp_path, "--leg-length", "0.25:0.35:3"))
    assert data["designs"] == data["computed"] == 3 and data["invalid"] == 0
    assert data["axes"] == {"leg_length": [0.25, 0.3, 0.35]}
    assert data["mode"] == "fixed-cube"
    assert Path(data["plot"]).read_bytes().startswith(PNG_MAGIC)
    table = pd.read_parquet(data["parquet"])
    assert table["leg_length"].tolist() == [0.25, 0.3, 0.35]
    spec = SweepSpec(axes=(SweepAxis.parse("leg_length=0.25:0.35:3"),), grid=int(GRID))
    same = og.run_sweep(spec, tmp_path / "api", workers=1)
    pd.testing.assert_frame_equal(table, same.table)  # the command is the Python sweep
    code, out, _ = run(capsys, *_sweep(tmp_path, "--leg-length", "0.25:0.35:3"))
    assert code == 0
    assert "0 computed, 3 already done, 0 invalid" in out
    assert "300.00" in out and "results.csv" in out


def test_product_with_parameters(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    data = run_json(
        capsys,
        *_sweep(tmp_path, "--leg-length", "0.2,0.31", "--no-plot"),
        "--param",
        "psi_max=2,3",
        "--param",
        "parallelogram_width=0.1",
        "--param",
        "tool_offset=0,0,0.25",
    )
    assert data["axes"] == {"leg_length": [0.2, 0.31], "psi_max": [2.0, 3.0]}
    assert data["designs"] == 4 and data["invalid"] == 2 and data["plot"] is None
    table = pd.read_csv(data["csv"])
    assert table["psi_max"].tolist() == [2.0, 3.0, 2.0, 3.0]
    assert table["status"].tolist() == ["invalid", "invalid", "ok", "ok"]
    widths = og.prototype().replace(parallelogram_width=0.1, tool_offset=(0, 0, 0.25))
    assert table["moving_mass"][2] == pytest.approx(og.inertia_table(widths).total_moving_mass)


def test_redesign_mode(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    data = run_json(
        capsys,
        *_sweep(tmp_path, "--mode", "redesign", "--workspace", "0.2", "--psi", "0.5", "2"),
    )
    table = pd.read_parquet(data["parquet"])
    assert len(table) == 1 and data["plot"] is None
    assert table["stroke"][0] == pytest.approx(PAPER_STROKE, abs=PAPER_LENGTH_TOL)
    assert table["leg_length"][0] > PROTOTYPE_LEG


@pytest.mark.parametrize(
    ("extra", "mentions"),
    [
        (["--leg-length", "0.2:0.4"], "START:STOP:N"),
        (["--param", "slider_lower=-0.1"], "slider limits"),
        (["--param", "wheel_size=1,2"], "sweep axis"),
        (["--param", "leg_length=0.3,0.31", "--leg-length", "0.3"], "each axis given once"),
        (["--mode", "redesign", "--leg-length", "0.3", "--param", "cube_side=0.2,0.3"], "both"),
        (["--workspace", "nan"], "--workspace"),
        (["--grid", "1"], "--grid"),
        (["--workers", "0"], "--workers"),
        (["--scheduler", "somewhere"], "scheduler"),
        (["--mode", "other"], "--mode"),
        (["--grid", "1000000000"], "grid=1000000000"),
        (["--requirement-grid", "200"], "requirement_grid=200"),
        (["--workers", "1000"], "workers=1000"),
        (["--leg-length", "0.25:0.45:200", "--param", "psi_max=2:3:100"], "designs=20000"),
    ],
)
def test_bad_input_exits_2(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, extra: list[str], mentions: str
) -> None:
    code, out, err = run(capsys, *_sweep(tmp_path, *extra))
    assert code == ERROR
    assert out == ""
    assert mentions in err
    last = err.strip().splitlines()[-1]  # ours, or argparse's usage error
    assert last.startswith("orthoglide sweep: error:")
    assert not (tmp_path / "parts").exists()  # refused before anything is written


def _table_lines(out: str) -> list[list[str]]:
    """The terminal table: the header's and each design's cells (split on 2+ spaces)."""
    import re

    lines = out.splitlines()
    start = next(k for k, line in enumerate(lines) if line.strip().startswith("L [mm]"))
    return [re.split(r"\s{2,}", line.strip()) for line in lines[start:]]


def test_every_swept_quantity_has_a_column(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    extra = ["--leg-length", "0.3,0.32", "--param", "bar_radius=0.008,0.012", "--no-plot"]
    code, out, err = run(capsys, *_sweep(tmp_path, *extra))
    assert code == 0, err
    header, *rows = _table_lines(out)
    assert header[:3] == ["L [mm]", "Lw [mm]", "bar_radius [mm]"]
    assert [row[:3] for row in rows] == [
        ["300.00", "200.00", "8"],
        ["300.00", "200.00", "12"],
        ["320.00", "200.00", "8"],
        ["320.00", "200.00", "12"],
    ]
    table = pd.read_csv(tmp_path / "results.csv")
    stroke = header.index("stroke [mm]")
    assert [float(row[stroke]) for row in rows] == pytest.approx(
        (1e3 * table["stroke"]).round(2).tolist()
    )


def test_a_second_axis_shows_beside_the_first(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    extra = ["--leg-length", "0.31", "--param", "psi_max=2,3", "--param", "actuator_stiffness=5e7"]
    code, out, _ = run(capsys, *_sweep(tmp_path, *extra, "--no-plot"))
    assert code == 0
    header, *rows = _table_lines(out)
    assert header[2] == "psi_max" and [row[2] for row in rows] == ["2", "3"]
    assert "actuator_stiffness [N/um]" not in header  # set, not swept


def test_the_plot_marks_the_users_design(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from orthoglide_pin.sweep import plots

    drawn = []

    def spy(*args: object, **kwargs: object) -> object:
        fig = original(*args, **kwargs)
        drawn.append(fig)
        return fig

    original = plots.sweep_figure
    monkeypatch.setattr(plots, "sweep_figure", spy)
    user = og.prototype().replace(leg_length=0.35, slider_lower=None, slider_upper=None)
    config = user.save(tmp_path / "mine.yaml")
    out = tmp_path / "sweep"
    code, _, err = run(capsys, *_sweep(out, "--config", str(config), "--leg-length", "0.33,0.37"))
    assert code == 0, err
    (fig,) = drawn
    for ax in fig.axes:
        marks = [line for line in ax.get_lines() if line.get_label() == plots.DESIGN_LABEL]
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [350.0, 350.0]
        labels = {line.get_label() for line in ax.get_lines()}
        assert plots.PROTOTYPE_LABEL not in labels and "paper" not in labels
        assert ax.get_xlabel() == "leg length [mm]"
    drawn.clear()
    code, _, err = run(capsys, *_sweep(tmp_path / "paper", "--leg-length", "0.3,0.32"))
    assert code == 0, err
    stroke = drawn[0].axes[0]
    labels = [line.get_label() for line in stroke.get_lines()]
    assert plots.PROTOTYPE_LABEL in labels and "paper" in labels


def test_the_sweep_judges_by_the_machines_criterion(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    config = tmp_path / "d.yaml"
    og.design_from_workspace(0.25, 0.4, 2.5, grid_points=2).to_params().save(config)
    argv = (*_sweep(tmp_path / "own", "--config", str(config)), "--requirement-grid", "2")
    data = run_json(capsys, *argv)
    assert data["criterion"] == {
        "psi_min": 0.4,
        "psi_max": 2.5,
        "tolerance": 1e-4,
        "from": "machine",
    }
    table = pd.read_parquet(data["parquet"])
    assert table["psi_min"].tolist() == [0.4] and table["psi_max"].tolist() == [2.5]
    assert table["bounds_hold"].tolist() == [True]
    code, out, _ = run(capsys, *argv)
    assert code == 0 and "criterion factors in [0.4, 2.5] (within 0.0001), the machine's" in out
    assert "  holds  " in out and "    yes  " in out
    # --psi overrides it; a psi axis is an axis, whatever the base says
    tight = run_json(capsys, *_sweep(tmp_path / "psi", "--config", str(config)),
                     "--requirement-grid", "2", "--psi", "0.5", "2")  # fmt: skip
    assert tight["criterion"]["from"] == "--psi"
    assert pd.read_parquet(tight["parquet"])["bounds_hold"].tolist() == [False]
    axis = run_json(capsys, *_sweep(tmp_path / "axis", "--config", str(config), "--no-plot"),
                    "--requirement-grid", "2", "--param", "psi_max=2.4:2.5:2")  # fmt: skip
    assert axis["axes"] == {"psi_max": [2.4, 2.5]}
    holds = pd.read_parquet(axis["parquet"])["bounds_hold"].tolist()
    assert holds == [False, True]


def test_sweep_with_a_program(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    prog = tmp_path / "part.nc"
    prog.write_text("G21 G90\nG0 X40 Y-30\nG1 Y30 F9000\nG0 X0 Y0\nM2\n")
    argv = _sweep(tmp_path / "s", "--leg-length", "0.28,0.34", "--requirement-grid", "2")
    data = run_json(capsys, *argv, "--program", str(prog), "--no-plot")
    table = pd.read_parquet(data["parquet"])
    assert table["cycle_time"].gt(0.05).all() and table["binding_limit"].str.len().gt(0).all()
    spec = SweepSpec(
        axes=(SweepAxis.parse("leg_length=0.28,0.34"),),
        grid=int(GRID),
        requirement_grid=2,
        program=prog.read_text(),
    )
    same = og.run_sweep(spec, tmp_path / "api", workers=1)
    pd.testing.assert_frame_equal(table, same.table)  # the command is the Python sweep
    code, out, _ = run(capsys, *argv, "--program", str(prog), "--no-plot")
    assert code == 0 and "cycle [s]" in out and "binding" in out
    assert "0 computed, 2 already done" in out
    # another program into the same directory is refused, naming the program
    prog.write_text("G21 G90\nG0 X40\nM2\n")
    code, out, err = run(capsys, *argv, "--program", str(prog), "--no-plot")
    assert code == ERROR and "program.sha256" in err


def test_sweep_with_a_program_and_a_cut_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    pytest.importorskip("toppra")
    prog = tmp_path / "part.nc"
    prog.write_text("G21 G90 G17\nG0 X-20 Y-10 Z5\nG1 Z-2 F600\nG1 X20 F3000\nG1 Y10\nG0 Z5\n")
    cut = str(og.shipped_cut_file())
    argv = _sweep(tmp_path / "s", "--leg-length", "0.31,0.34", "--requirement-grid", "2")
    argv = (*argv, "--program", str(prog), "--no-plot")
    code, out, _ = run(capsys, *argv, "--cut", cut)
    assert code == 0 and "surface [um]" in out and "margin" in out
    assert "as `orthoglide accuracy` computes them, the default drive train reflected" in out
    assert "the sliders within 1200 mm/s and 20 m/s^2" in out and "no motor limit" in out
    table = pd.read_csv(tmp_path / "s" / "results.csv")
    assert table["surface_error_max"].between(1e-6, 1e-3).all()
    assert table["stability_margin_min"].gt(0.0).all()
    code, out, err = run(capsys, *argv)  # the same sweep without its cut file: refused
    assert code == ERROR and "cut" in err and len(err.strip().splitlines()) == 1
    out_dir = tmp_path / "none"
    code, out, err = run(capsys, *_sweep(out_dir, "--cut", cut))
    assert (code, out) == (ERROR, "") and "--cut" in err and "--program" in err
    assert not out_dir.exists()


def test_sweep_refuses_a_bad_program(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    pytest.importorskip("toppra")
    bad = tmp_path / "bad.nc"
    bad.write_text("G21\nG1 X10\n")
    out = tmp_path / "s"
    for path, says in ((bad, "program line 2"), (tmp_path / "none.nc", "program")):
        code, text, err = run(capsys, *_sweep(out, "--program", str(path)))
        assert (code, text) == (ERROR, "") and says in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
