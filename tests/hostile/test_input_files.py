"""Input files: special files and empty paths are refused, as they are for outputs.

A FIFO given as ``--config`` used to be read as an empty file (the defaults
applied silently), ``/dev/null`` too, and ``view --static ""`` started the
live server. Every input path is now a regular file or one line, exit 2.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import socket
from collections.abc import Iterator
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin._io import read_yaml_mapping
from orthoglide_pin.cli import build_parser
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.exceptions import OutputPathError
from tests.conftest import run

#: Each command that reads a file, the option naming it and the arguments it needs.
READERS = [
    ("summary", "--config", ()),
    ("report", "--motor", ("--out", "report")),
    ("report", "--cut", ("--out", "report")),
    ("dynamics", "--motor", ("--point", "0", "0", "0")),
    ("sweep", "--motor", ("--leg-length", "0.3,0.31", "--out", "sweep")),
    ("drive", "--check", ()),
    ("view", "--motor", ("--mode", "1", "--at", "0", "0", "0", "--static", "mode.html")),
]


@contextlib.contextmanager
def _unix_socket(path: Path) -> Iterator[Path]:
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(path))
        yield path


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    path = tmp_path / "pipe.yaml"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize(("command", "option", "extra"), READERS)
def test_a_fifo_is_refused_by_every_command_that_reads_a_file(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    fifo: Path,
    command: str,
    option: str,
    extra: tuple[str, ...],
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, command, option, str(fifo), *extra)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "it is a named pipe (FIFO)" in err and str(fifo) in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.yaml"]  # nothing written


def test_a_sweeps_cut_file_is_read_as_every_input(fifo: Path) -> None:
    from orthoglide_pin.sweep.accuracy import check_cut

    program = "G21 G90\nG1 X10 F1000\n"
    for path, says in ((fifo, "named pipe"), ("", "an empty path"), ("/dev/zero", "device")):
        with pytest.raises(og.InvalidParameterError, match=says):
            check_cut(path, program)


@pytest.mark.parametrize("device", ["/dev/null", "/dev/zero"])
@pytest.mark.parametrize("loader", [og.OrthoglideParams.load, load_drive, og.read_cut_file])
def test_devices_are_refused_not_read(device: str, loader: object) -> None:
    assert callable(loader)
    with pytest.raises(og.InvalidParameterError, match=r"it is a character device"):
        loader(device)


def test_a_socket_is_refused(tmp_path: Path) -> None:
    with (
        _unix_socket(tmp_path / "s.yaml") as path,
        pytest.raises(og.InvalidParameterError, match=r"it is a socket"),
    ):
        read_yaml_mapping(path, "config")


def test_a_link_to_a_regular_file_is_read(tmp_path: Path) -> None:
    target = tmp_path / "real.yaml"
    target.write_text("leg_length: 0.32\n")
    link = tmp_path / "link.yaml"
    link.symlink_to(target)
    assert og.OrthoglideParams.load(link).leg_length == 0.32
    fifo_link = tmp_path / "fifo-link.yaml"
    os.mkfifo(tmp_path / "p")
    fifo_link.symlink_to(tmp_path / "p")
    with pytest.raises(og.InvalidParameterError, match="FIFO"):
        og.OrthoglideParams.load(fifo_link)


@pytest.mark.parametrize("loader", [og.OrthoglideParams.load, load_drive, og.read_cut_file])
def test_an_empty_path_is_refused_by_the_api(loader: object) -> None:
    assert callable(loader)
    with pytest.raises(og.InvalidParameterError, match=r"an empty path names no file"):
        loader("")


def test_a_mesh_that_is_a_fifo_or_a_device_is_refused_by_name(fifo: Path) -> None:
    special = fifo.with_suffix(".stl")
    fifo.rename(special)
    with pytest.raises(og.InvalidParameterError, match=r"meshes\.bar\.file.*named pipe"):
        og.prototype().replace(meshes={"bar": str(special)})


def _path_options() -> list[tuple[str, str, list[str]]]:
    """Every (command, path option, argv with that option empty) of the command line."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    cases = []
    for name, command in sub.choices.items():
        required: list[str] = []
        for action in command._actions:
            if not action.option_strings:
                required += ["0"] * (action.nargs if isinstance(action.nargs, int) else 1)
            elif action.required:
                nargs = action.nargs if isinstance(action.nargs, int) else 1
                required += [action.option_strings[-1], *["x"] * nargs]
        for action in command._actions:
            metavar = action.metavar if isinstance(action.metavar, str) else ""
            if action.option_strings and (metavar.startswith("FILE") or metavar == "DIR"):
                option = action.option_strings[-1]
                argv = [name, *required]
                if option in argv:
                    argv[argv.index(option) + 1] = ""
                else:
                    argv += [option, ""]
                cases.append((name, option, argv))
    return cases


PATH_OPTIONS = _path_options()


def test_the_path_options_are_found() -> None:
    found = {(c, o) for c, o, _ in PATH_OPTIONS}
    assert {("view", "--static"), ("summary", "--config"), ("sweep", "--out")} <= found
    assert {("report", "--motor"), ("urdf", "--package-dir"), ("drive", "--check")} <= found
    assert ("design", "--write-config") in found and ("map", "--csv") in found


@pytest.mark.parametrize(("command", "option", "argv"), PATH_OPTIONS)
def test_an_empty_path_is_refused_by_every_path_option(
    capsys: pytest.CaptureFixture[str], command: str, option: str, argv: list[str]
) -> None:
    with pytest.raises(SystemExit) as info:
        build_parser().parse_args(argv)
    err = capsys.readouterr().err
    assert info.value.code == 2 and err.count("\n") == 1
    assert f"argument {option}" in err or option in err
    assert "an empty path" in err


def test_an_empty_config_does_not_fall_back_to_the_prototype(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, err = run(capsys, "summary", "--config", "")
    assert code == 2 and out == "" and "an empty path" in err


def test_loop_data_is_read_as_every_input(tmp_path: Path, fifo: Path) -> None:
    with pytest.raises(og.DescriptionError, match=r"it is a named pipe \(FIFO\)"):
        og.read_loops(fifo)
    with pytest.raises(og.DescriptionError, match="an empty path names no file"):
        og.read_loops("")
    urdf = og.write_urdf(tmp_path / "m.urdf")
    assert og.read_loops(og.loops_path(urdf)) == og.load_loops()


def test_a_fifo_where_the_loop_data_goes_is_refused_not_opened(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "m.loops.yaml")
    with pytest.raises(OutputPathError, match=r"named pipe \(FIFO\)"):
        og.write_urdf(tmp_path / "m.urdf")  # opening it to read its first line would block
    assert not (tmp_path / "m.urdf").exists()


def test_an_empty_output_path_is_refused_by_the_api(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # "" must never mean the current directory
    spec = og.SweepSpec(axes=(og.SweepAxis.parse("leg_length=0.31"),), grid=4, requirement_grid=3)
    writers = {
        "run_sweep": lambda: og.run_sweep(spec, "", workers=1, progress=False),
        "save": lambda: og.prototype().save(""),
        "write_urdf": lambda: og.write_urdf(""),
    }
    for name, write in writers.items():
        with pytest.raises(OutputPathError, match="an empty path") as info:
            write()
        assert str(info.value).startswith("cannot write '': an empty path"), name
    assert list(tmp_path.iterdir()) == []
