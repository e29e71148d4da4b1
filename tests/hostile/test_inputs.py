"""Hostile configuration and drive files, and error messages that stay short."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin._io import MAX_INPUT_BYTES, MAX_YAML_DEPTH
from orthoglide_pin.drives.motor import load_drive
from orthoglide_pin.exceptions import MAX_VALUE_CHARS, InvalidParameterError
from tests.conftest import run

#: Longest an error message may be: the fixed text plus the shortened value [chars].
MESSAGE_BUDGET = 400
#: Seconds a refused file may take to be refused (a hang shows as a timeout).
REFUSAL_TIMEOUT = 60.0

#: A "billion laughs": nine levels of nine aliases (9^9 strings once expanded).
BOMB = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"{n}: &{n} [{', '.join([f'*{p}'] * 9)}]\n"
    for p, n in zip("abcdefgh", "bcdefghi", strict=True)
)

Loader = Callable[[Path], object]
LOADERS: dict[str, Loader] = {
    "config": og.OrthoglideParams.load,
    "motor file": load_drive,
    "cut file": og.read_cut_file,
}


def _refused(loader: Loader, path: Path | str) -> InvalidParameterError:
    """Call ``loader(path)`` in a thread; it must refuse within the timeout."""
    box: dict[str, BaseException | object] = {}

    def target() -> None:
        try:
            box["result"] = loader(Path(path))
        except BaseException as exc:
            box["error"] = exc

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(REFUSAL_TIMEOUT)
    assert not thread.is_alive(), f"reading {path} did not end within {REFUSAL_TIMEOUT} s"
    error = box.get("error")
    assert isinstance(error, InvalidParameterError), box
    message = str(error)
    assert "\n" not in message and len(message) < MESSAGE_BUDGET, message
    return error


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_a_yaml_bomb_is_refused_at_its_first_alias(tmp_path: Path, what: str) -> None:
    path = tmp_path / "bomb.yaml"
    path.write_text(BOMB)
    error = _refused(LOADERS[what], path)
    assert "alias *a" in str(error) and str(path) in str(error)
    assert error.name == what


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_merge_keys_are_aliases_too(tmp_path: Path, what: str) -> None:
    path = tmp_path / "merge.yaml"
    path.write_text("base: &b {leg_length: 0.3}\nother:\n  <<: *b\n")
    assert "alias" in str(_refused(LOADERS[what], path))


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_files_that_are_not_utf8_are_named_with_the_bad_offset(tmp_path: Path, what: str) -> None:
    path = tmp_path / "latin1.yaml"
    text = "leg_length: 0.31 # longueur de la jambe, mesurée\n"
    path.write_bytes(text.encode("latin-1"))
    message = str(_refused(LOADERS[what], path))
    assert "not a text file" in message and str(path) in message
    assert f"a byte that is not UTF-8 at offset {text.index('é')}" in message
    assert "0xe9" not in message and "longueur" not in message  # never the content


def test_a_byte_order_mark_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.yaml"
    path.write_bytes(b"\xef\xbb\xbfleg_length: 0.33\n")
    assert og.OrthoglideParams.load(path).leg_length == pytest.approx(0.33, rel=0, abs=0)


@pytest.mark.parametrize(
    ("text", "key"),
    [("1: 2\n", "1"), ("true: 1\n", "True"), ("1.5: 1\n", "1.5"), ("null: 3\n", "None")],
)
@pytest.mark.parametrize("what", sorted(LOADERS))
def test_keys_must_be_strings(tmp_path: Path, what: str, text: str, key: str) -> None:
    path = tmp_path / "keys.yaml"
    path.write_text(text)
    error = _refused(LOADERS[what], path)
    assert error.name == f"{what} key" and str(error).startswith(f"invalid {what} key={key}")


def test_nested_keys_must_be_strings_too(tmp_path: Path) -> None:
    path = tmp_path / "drive.yaml"
    path.write_text("drive_train:\n  3: 0.01\n")
    assert _refused(load_drive, path).name == "motor file key"


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_files_over_the_cap_are_refused_before_parsing(tmp_path: Path, what: str) -> None:
    path = tmp_path / "big.yaml"
    line = "# padding\n"
    path.write_text(line * (MAX_INPUT_BYTES // len(line) + 1))
    assert path.stat().st_size > MAX_INPUT_BYTES
    assert "at most 1000000 bytes" in str(_refused(LOADERS[what], path))
    path.write_text(line * (MAX_INPUT_BYTES // len(line)))  # just under: an empty config
    if what == "cut file":  # read, then refused for the sections it lacks
        assert "tool section" in str(_refused(LOADERS[what], path))
    else:
        assert LOADERS[what](path) is not None


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_dev_zero_and_a_directory_are_refused(tmp_path: Path, what: str) -> None:
    assert "it is a character device" in str(_refused(LOADERS[what], "/dev/zero"))
    assert "directory" in str(_refused(LOADERS[what], tmp_path))
    missing = tmp_path / "missing.yaml"
    message = str(_refused(LOADERS[what], missing))
    assert str(missing) in message and "No such file" in message


@pytest.mark.parametrize("what", sorted(LOADERS))
def test_a_fifo_without_writer_is_refused_not_read_as_empty(tmp_path: Path, what: str) -> None:
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    message = str(_refused(LOADERS[what], fifo))
    assert "it is a named pipe (FIFO)" in message and str(fifo) in message


def test_deep_nesting_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "deep.yaml"
    path.write_text("a: " + "[" * (MAX_YAML_DEPTH + 2) + "]" * (MAX_YAML_DEPTH + 2) + "\n")
    assert "nested levels" in str(_refused(og.OrthoglideParams.load, path))
    path.write_text("[" * 20_000 + "]" * 20_000)  # deeper than Python's recursion limit
    assert "nest" in str(_refused(og.OrthoglideParams.load, path))  # libyaml: nesting depth


def test_from_yaml_text_applies_the_same_rules() -> None:
    with pytest.raises(InvalidParameterError, match="alias"):
        og.OrthoglideParams.from_yaml(BOMB)
    with pytest.raises(InvalidParameterError, match="key=1"):
        og.OrthoglideParams.from_yaml("1: 2")
    with pytest.raises(InvalidParameterError, match="a YAML document"):
        og.OrthoglideParams.from_yaml(b"leg_length: 0.3")  # type: ignore[arg-type]
    assert og.OrthoglideParams.from_yaml("leg_length: 0.33").leg_length == 0.33


def test_the_cli_refuses_a_bomb_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "bomb.yaml"
    path.write_text(BOMB)
    code, out, err = run(capsys, "summary", "--config", str(path))
    assert code == 2 and out == ""
    assert err.startswith("orthoglide summary: error: invalid config=") and err.count("\n") == 1


# ----------------------------------------------------------- short messages
def test_huge_values_are_shortened_in_messages_and_kept_whole() -> None:
    value = "x" * 10_000_000
    error = InvalidParameterError("name", value, "something shorter")
    shown = str(error).split("=", 1)[1].split(": expected")[0]
    assert len(shown) <= MAX_VALUE_CHARS + len(" (10000000 characters)")
    assert shown.endswith("... (10000000 characters)")
    assert error.value is value


def test_huge_containers_are_shortened_without_expanding_them() -> None:
    value = list(range(10**6))
    error = InvalidParameterError("points", value, "three numbers")
    assert len(str(error)) < MESSAGE_BUDGET and error.value is value
    nested = {"a": [[1.0] * 1000] * 1000}
    assert len(str(InvalidParameterError("config", nested, "x"))) < MESSAGE_BUDGET


def test_short_values_are_shown_as_before() -> None:
    assert str(InvalidParameterError("leg_length", -0.3, "a positive number")) == (
        "invalid leg_length=-0.3: expected a positive number"
    )
    array_message = str(InvalidParameterError("p", np.ones((1000, 3)), "x"))
    assert "\n" not in array_message and len(array_message) < MESSAGE_BUDGET


def test_a_long_yaml_value_is_shortened_in_the_parameter_error(tmp_path: Path) -> None:
    path = tmp_path / "long.yaml"
    path.write_text("leg_length: " + "9" * 500_000 + "x\n")
    message = str(_refused(og.OrthoglideParams.load, path))
    assert message.startswith("invalid leg_length='999") and "(500001 characters)" in message
