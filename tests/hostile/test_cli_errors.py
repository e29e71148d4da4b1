"""Careless command lines: one error line, --version, defaults in --help, negative numbers."""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import pytest
from conftest import run

from orthoglide_pin.cli import build_parser

#: Exit status of every usage or input error.
ERROR = 2


def sub_parsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise AssertionError("no sub-commands")


def assert_one_error_line(code: int, out: str, err: str, prefix: str, mentions: str) -> None:
    assert code == ERROR, err
    assert out == ""
    assert err.endswith("\n") and err.count("\n") == 1, err  # exactly one line
    assert err.startswith(f"{prefix}: error: "), err
    assert "usage:" not in err and "Traceback" not in err
    assert mentions in err


# ------------------------------------------------------------ one error line
@pytest.mark.parametrize(
    ("argv", "command", "mentions"),
    [
        (["ik", "0.01"], "ik", "Y, Z"),
        (["ik", "0", "0", "0", "0"], "ik", "unrecognized arguments: 0"),
        (["fk", "0", "0", "0", "--bogus"], "fk", "--bogus"),
        (["jacobian", "0", "0", "0", "--method", "magic"], "jacobian", "invalid choice: 'magic'"),
        (["map", "--index", "nonsense", "--out", "m.png"], "map", "'nonsense'"),
        (["map"], "map", "--out"),
        (["design", "--psi", "0.5"], "design", "--psi"),
        (
            ["design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "many"],
            "design",
            "many",
        ),
        (["view", "--port", "70000"], "view", "70000"),
        (["view", "--grid", "x"], "view", "--grid"),
        (["sweep", "--out", "d", "--workers", "0"], "sweep", "--workers"),
        (["report", "--resolution", "fine"], "report", "'fine'"),
        (["dynamics"], "dynamics", "--point"),
        (["dynamics", "--point"], "dynamics", "--point"),
        ([], None, "COMMAND"),
        (["frobnicate"], None, "invalid choice: 'frobnicate'"),
        (["--bogus"], None, "COMMAND"),
    ],
)
def test_a_usage_error_is_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], command: str | None, mentions: str
) -> None:
    prefix = "orthoglide" if command is None else f"orthoglide {command}"
    assert_one_error_line(*run(capsys, *argv), prefix, mentions)


@pytest.mark.parametrize(
    ("argv", "mentions"),
    [
        (["ik", "0", "0", "zero"], "'zero'"),
        (["ik", "0", "0", "nan"], "'nan'"),
        (["dynamics", "--point", "0", "0"], "--point"),
        (["dynamics", "--point", "0,0,0,0"], "--point"),
        (["dynamics", "--point", "0", "0", "0", "--velocity", "1e999", "0", "0"], "--velocity"),
    ],
)
def test_a_bad_value_is_one_line(
    capsys: pytest.CaptureFixture[str], argv: list[str], mentions: str
) -> None:
    assert_one_error_line(*run(capsys, *argv), f"orthoglide {argv[0]}", mentions)


def test_help_still_shows_the_usage(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "ik", "--help")
    assert (code, err) == (0, "")
    assert out.startswith("usage: orthoglide ik ")


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "--version")
    assert (code, err) == (0, "")
    assert out == f"orthoglide {importlib.metadata.version('orthoglide-pin')}\n"


# ------------------------------------------------------------ every default
def _shown(default: Any) -> str:
    return " ".join(map(str, default)) if isinstance(default, (list, tuple)) else str(default)


def _forms(default: str) -> set[str]:
    """How a default may read in a help text: as given, or a number in short form (1.0: 1)."""
    try:
        return {default, f"{float(default):g}"}
    except ValueError:
        return {default}


def _defaults() -> list[tuple[str, str, str]]:
    """(command, option, default text) of every option that has a default."""
    found = []
    for name, parser in sub_parsers().items():
        for action in parser._actions:
            default = action.default
            if (
                not action.option_strings
                or default in (None, False, argparse.SUPPRESS)
                or (isinstance(default, list) and not default)
            ):
                continue
            found.append((name, action.option_strings[-1], _shown(default)))
    return found


def test_every_command_has_defaults_to_show() -> None:
    commands = {c for c, _, _ in _defaults()}
    assert {"design", "map", "report", "sweep", "view", "jacobian", "indices"} <= commands


@pytest.mark.parametrize(("command", "option", "default"), _defaults())
def test_help_shows_every_default(command: str, option: str, default: str) -> None:
    parser = sub_parsers()[command]
    action = next(a for a in parser._actions if option in a.option_strings)
    formatter = parser._get_formatter()
    formatter.add_argument(action)
    text = " ".join(formatter.format_help().split())
    assert "default" in text.lower(), text
    assert any(form in text for form in _forms(default)), text
    assert not any(f"({form}) (default: " in text for form in _forms(default)), text  # once


# ------------------------------------------------------------ negative numbers
@pytest.mark.parametrize(
    ("argv", "dest", "expected"),
    [
        (["ik", "-0.05", "-.02", "-1e-3"], "z", "-1e-3"),
        (["fk", "-0.01", "0", "-inf"], "q3", "-inf"),
        (["dynamics", "--point", "-0.05,0,0"], "point", ["-0.05,0,0"]),
        (["dynamics", "--point", "-0.05", "0", "0"], "point", ["-0.05", "0", "0"]),
        (
            ["dynamics", "--point", "0,0,0", "--velocity", "-1", "0", "0"],
            "velocity",
            ["-1", "0", "0"],
        ),
        (
            ["dynamics", "--point", "0,0,0", "--acceleration", "-20,0,-1"],
            "acceleration",
            ["-20,0,-1"],
        ),
        (
            ["dynamics", "--point", "0,0,0", "--wrench", "-10", "0", "0"],
            "wrench",
            ["-10", "0", "0"],
        ),
        (
            ["dynamics", "--point", "0,0,0", "--gravity", "0", "0", "-9.81"],
            "gravity",
            ["0", "0", "-9.81"],
        ),
        (["report", "--gravity", "-9.81,0,0"], "gravity", ["-9.81,0,0"]),
        (["report", "--corner", "-0.07", "-0.07", "-0.07"], "corner", ["-0.07", "-0.07", "-0.07"]),
        (["view", "--point", "-0.05,0,0"], "point", "-0.05,0,0"),
        (["view", "--ellipsoids", "-0.05,0,0;0,-0.02,0"], "ellipsoids", "-0.05,0,0;0,-0.02,0"),
        (["map", "--out", "m.png", "--extent", "-0.3", "0.3"], "extent", ["-0.3", "0.3"]),
        (["map", "--out", "m.png", "--slice", "z=-0.05"], "slice", "z=-0.05"),
        (["sweep", "--out", "d", "--corner", "-0.1", "-0.1", "-0.1"], "corner", ["-0.1"] * 3),
    ],
)
def test_negative_numbers_are_values(argv: list[str], dest: str, expected: Any) -> None:
    assert getattr(build_parser().parse_args(argv), dest) == expected


def test_a_point_as_words_or_as_one_list(capsys: pytest.CaptureFixture[str]) -> None:
    words = run(
        capsys, "dynamics", "--point", "-0.05", "0", "0.01", "--velocity", "-1", "0", "0", "--json"
    )
    listed = run(capsys, "dynamics", "--point", "-0.05,0,0.01", "--velocity", "-1,0,0", "--json")
    assert words[0] == listed[0] == 0, (words[2], listed[2])
    assert json.loads(words[1]) == json.loads(listed[1])
    assert json.loads(listed[1])["motor_speeds_rpm"][0] < 0  # the minus sign was kept


# ------------------------------------------------------------ library warnings
def _patched_run(patch: str, argv: list[str]) -> subprocess.CompletedProcess[str]:
    """Run ``main(argv)`` in a fresh interpreter after ``patch`` (Python source)."""
    source = (
        textwrap.dedent(patch)
        + f"\nfrom orthoglide_pin.cli import main\nraise SystemExit(main({argv!r}))\n"
    )
    return subprocess.run(
        [sys.executable, "-c", source], capture_output=True, text=True, timeout=120, check=False
    )


WARNING_PATCH = """
import warnings
import numpy as np
import orthoglide_pin.kinematics.closed_form as cf
real = cf.inverse_kinematics
def noisy(*args, **kwargs):
    np.log(np.zeros(1))                       # RuntimeWarning: divide by zero
    warnings.warn("a library's warning", UserWarning)
    return real(*args, **kwargs)
cf.inverse_kinematics = noisy
"""


def test_library_warnings_never_reach_the_terminal() -> None:
    done = _patched_run(WARNING_PATCH, ["ik", "0.01", "0", "0"])
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    assert done.stdout.startswith("q = (")


CHILD_PATCH = """
import subprocess, sys
import orthoglide_pin.kinematics.closed_form as cf
real = cf.inverse_kinematics
def with_a_worker(*args, **kwargs):  # a process started by the command, as a sweep's worker
    subprocess.run([sys.executable, "-c", "import warnings; warnings.warn('from a worker')"])
    return real(*args, **kwargs)
cf.inverse_kinematics = with_a_worker
"""


def test_warnings_of_started_processes_never_reach_the_terminal() -> None:
    done = _patched_run(CHILD_PATCH, ["ik", "0.01", "0", "0"])
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""


NAN_PATCH = """
import numpy as np
import orthoglide_pin.kinematics.closed_form as cf
def broken(*args, **kwargs):
    return np.sqrt(np.array([-1.0, 0.0, 0.0]))  # RuntimeWarning, then a NaN
cf.direct_kinematics = broken
"""


def test_what_a_warning_meant_becomes_one_error_line() -> None:
    done = _patched_run(NAN_PATCH, ["fk", "0", "0", "0", "--json"])
    assert_one_error_line(done.returncode, done.stdout, done.stderr, "orthoglide fk", "p[0]")
    assert "RuntimeWarning" not in done.stderr


def test_patched_runner_is_sound() -> None:
    """The helper above runs the real command (a control for the two tests above)."""
    done = _patched_run("", ["ik", "0", "0", "0", "--json"])
    assert done.returncode == 0 and json.loads(done.stdout)["q"] == [0.0, 0.0, 0.0]


# ------------------------------------------------------------ the command in every error
@pytest.mark.parametrize("command", sorted(sub_parsers()))
def test_every_usage_error_names_its_command(
    capsys: pytest.CaptureFixture[str], command: str
) -> None:
    code, out, err = run(capsys, command, "--no-such-option")
    assert_one_error_line(code, out, err, f"orthoglide {command}", "")


@pytest.mark.parametrize(
    ("argv", "mentions"),
    [
        (["plan", "no-such.nc", "--out", "o"], "invalid program='no-such.nc'"),
        (["summary", "--config", "no-such.yaml"], "invalid config='no-such.yaml'"),
        (["drive", "--check", "no-such.yaml"], "invalid motor file='no-such.yaml'"),
        (["calibrate", "no-such.csv", "--out", "o"], "invalid measurements='no-such.csv'"),
    ],
)
def test_every_input_error_names_its_command(
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    tmp_path: Path,
    argv: list[str],
    mentions: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert_one_error_line(*run(capsys, *argv), f"orthoglide {argv[0]}", mentions)
    assert list(tmp_path.iterdir()) == []  # nothing written


# ------------------------------------------------------------ hostile values
#: An argument far longer than a message may quote, ending in a marker never shown.
HUGE_ARGUMENT = "x" * 1_000_000 + "SECRET-MARK"


@pytest.mark.parametrize(
    "argv",
    [
        ["plan", "p.nc", "--out", "o", "--dt", HUGE_ARGUMENT],
        ["ik", HUGE_ARGUMENT, "0", "0"],
        ["ik", "0", "0", "0", "--param", f"{HUGE_ARGUMENT}=1"],
        ["ik", "0", "0", "0", "--param", f"leg_length={HUGE_ARGUMENT}"],
        ["jacobian", "0", "0", "0", "--method", HUGE_ARGUMENT],
        ["ik", "0", "0", "0", *[HUGE_ARGUMENT] * 3],
        ["view", "--grid", HUGE_ARGUMENT],
        [HUGE_ARGUMENT],
    ],
)
def test_a_huge_argument_is_quoted_by_80_characters(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    code, out, err = run(capsys, *argv)
    assert (code, out) == (ERROR, "")
    assert err.count("\n") == 1 and len(err) < 700, err[:1000]
    assert "SECRET-MARK" not in err and "Traceback" not in err
    assert "x" * 60 in err and "characters" in err, err  # its beginning, and its length


def test_a_huge_path_is_cut_in_the_middle(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = run(capsys, "summary", "--config", "/" + HUGE_ARGUMENT)
    assert (code, out) == (ERROR, "") and err.count("\n") == 1 and len(err) < 500, err[:1000]
    assert (
        "'/xxxx" in err and "xxx...xxx" in err and f"({len(HUGE_ARGUMENT) + 1} characters)" in err
    )


@pytest.mark.parametrize(
    "argv",
    [
        ["ik", "0", "0", "a\x1b[31mb\nc"],
        ["ik", "0", "0", "0", "--param", "leg_length=a\x1b[31mb\nc"],
        ["jacobian", "0", "0", "0", "--method", "a\x1b[31mb\nc"],
        ["ik", "0", "0", "0", "a\x1b[31mb\nc"],
    ],
)
def test_control_characters_are_escaped(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    code, out, err = run(capsys, *argv)
    assert (code, out) == (ERROR, "") and err.count("\n") == 1, err
    assert "\x1b" not in err and "\\x1b[31m" in err, err


@pytest.mark.parametrize("command", ["plan", "simulate", "accuracy"])
def test_example_without_a_name_lists_the_names(
    capsys: pytest.CaptureFixture[str], command: str
) -> None:
    from orthoglide_pin.planning import EXAMPLE_PROGRAMS

    names = ", ".join(EXAMPLE_PROGRAMS)
    assert_one_error_line(
        *run(capsys, command, "--example"), f"orthoglide {command}", f"(one of {names})"
    )
