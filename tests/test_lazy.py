"""Optional packages: a missing extra is named in one line, before anything is written."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import run

import orthoglide_pin as og
from orthoglide_pin._lazy import EXTRAS, optional_import
from orthoglide_pin.exceptions import MissingExtraError

# Imported here, before any test hides them: a module imported for the first time
# while another is hidden would keep that state (pandas caches whether pyarrow exists).
pytest.importorskip("pandas")
pytest.importorskip("pyarrow")
pytest.importorskip("distributed")
pytest.importorskip("Pynite")
pytest.importorskip("toppra")


def test_a_missing_module_names_its_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(__import__("sys").modules, "pandas", None)  # import pandas fails
    with pytest.raises(MissingExtraError) as info:
        optional_import("pandas", "tables", "a sweep's table")
    error = info.value
    assert isinstance(error, ImportError) and isinstance(error, og.OrthoglideError)
    assert (error.module, error.extra) == ("pandas", "tables")
    assert str(error) == (
        "a sweep's table needs the optional package pandas, which is not installed: "
        "pip install 'orthoglide-pin[tables]'"
    )


def test_a_present_module_is_returned() -> None:
    assert optional_import("json", "tables").dumps([1]) == "[1]"


def test_the_extras_match_the_project_file() -> None:
    tomllib = pytest.importorskip("tomllib")
    text = (Path(__file__).resolve().parents[1] / "pyproject.toml").read_text()
    project = tomllib.loads(text)["project"]
    extras = project["optional-dependencies"]
    distribution = {
        "pandas": "pandas",
        "pyarrow": "pyarrow",
        "dask": "dask",
        "distributed": "dask",
        "Pynite": "PyNiteFEA",
        "openseespy": "openseespy",
        "toppra": "toppra",
        "mujoco": "mujoco",
    }
    for extra, modules in EXTRAS.items():
        for module in modules:
            dist = distribution[module]
            assert any(r.startswith(dist) for r in extras[extra]), (extra, module)
            assert not any(r.startswith(dist) for r in project["dependencies"]), module
    assert extras["all"] == ["orthoglide-pin[tables,cluster,fea,modal,plan,sim]"]
    assert not any(r.startswith("PyNiteFEA") for r in extras["test"])  # an extra, not a test tool


def test_the_mjcf_export_without_mujoco_says_sim(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setitem(__import__("sys").modules, "mujoco", None)
    with pytest.raises(MissingExtraError) as info:
        og.write_mjcf(tmp_path / "m.xml")
    assert str(info.value) == (
        "the MJCF export needs the optional package mujoco, which is not installed: "
        "pip install 'orthoglide-pin[sim]'"
    )
    assert list(tmp_path.iterdir()) == []


def test_the_frame_fea_without_pynite_says_fea(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(__import__("sys").modules, "Pynite", None)
    with pytest.raises(MissingExtraError) as info:
        og.frame_compliance([0.0, 0.0, 0.0])
    assert str(info.value) == (
        "the frame FEA check needs the optional package Pynite, which is not installed: "
        "pip install 'orthoglide-pin[fea]'"
    )


def test_planning_without_toppra_says_plan(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(__import__("sys").modules, "toppra", None)
    prog = tmp_path / "p.nc"
    prog.write_text("G1 X10 F600\n")
    code, out, err = run(
        capsys, "plan", str(prog), "--max-slider-acceleration", "5", "--out", str(tmp_path / "o")
    )
    assert code == 2 and out == ""
    assert err.strip().endswith("pip install 'orthoglide-pin[plan]'")
    assert err.count("\n") == 1 and not (tmp_path / "o").exists()


@pytest.mark.parametrize("blocked", ["pandas", "pyarrow"])
def test_sweep_without_the_table_stack_says_tables(
    blocked: str,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
) -> None:
    monkeypatch.setitem(__import__("sys").modules, blocked, None)
    out = tmp_path / "sweep"
    code, stdout, err = run(capsys, "sweep", "--leg-length", "0.3:0.32:2", "--out", str(out))
    assert (code, stdout) == (2, "")
    assert err == (
        "orthoglide sweep: error: a sweep (its results table) needs the optional package "
        f"{blocked}, "
        "which is not installed: pip install 'orthoglide-pin[tables]'\n"
    )
    assert not out.exists()


def test_a_scheduler_without_dask_says_cluster(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    out = tmp_path / "sweep"
    args = ("sweep", "--leg-length", "0.3:0.32:2", "--scheduler", "local", "--out", str(out))
    code, _, err = run(capsys, *args)
    assert code == 2
    assert err.endswith("pip install 'orthoglide-pin[cluster]'\n") and err.count("\n") == 1
    assert not out.exists()
