"""What a file holds never reaches a message: text checked first, sizes before reading.

Every input file (a program, a configuration, a drive, a calibration, the
measurements, a planned trajectory, loop data) is a regular file whose size is
checked before it is read, and text (UTF-8 without a NUL byte) before it is
parsed; an error names the offset of the first bad byte, never the content, and
quotes at most 80 characters of any value, escaped. Each case is run on the
command line (exit status 2, one line, no traceback) and in the API, and the
file carries a marker that must never be shown.
"""

from __future__ import annotations

import os
import re
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hostile._support import ORTHOGLIDE, TIMEOUT

import orthoglide_pin as og
from orthoglide_pin import _io
from orthoglide_pin.exceptions import MAX_VALUE_CHARS, OrthoglideError
from orthoglide_pin.planning.gcode import MAX_PROGRAM_BYTES
from orthoglide_pin.viewer.planned import read_trajectory
from tests.conftest import run

#: Exit status of every input error.
ERROR = 2
#: Text that stands for a secret: it is in every file and must appear in no message.
MARK = "SECRET-7f3a9c-MARK"
#: Longest error line accepted: the prefix, the path, 80 characters of value, the rule.
MAX_LINE = 700
#: A word far longer than any message may quote [characters].
HUGE = 1_000_000
#: A value far longer than a message may quote, in a file within the size caps.
LONG = 200_000

#: Each kind of input file: the command line reading ``{}`` and the API reading it.
READERS: dict[str, tuple[tuple[str, ...], Callable[[Path], Any]]] = {
    "program": (
        ("plan", "{}", "--out", "{}.out", "--max-slider-acceleration", "20"),
        og.read_program_file,
    ),
    "config": (("ik", "0", "0", "0", "--config", "{}"), og.OrthoglideParams.load),
    "motor file": (("drive", "--check", "{}"), og.load_drive),
    "calibration": (("ik", "0", "0", "0", "--calibration", "{}"), og.load_calibration),
    "measurements": (("calibrate", "{}", "--out", "{}.out"), og.read_measurements),
    "trajectory": (
        ("view", "--trajectory", "{}", "--static", "v.html"),
        lambda path: read_trajectory(path, og.OrthoglideParams()),
    ),
    "loop data": ((), og.read_loops),
}


def _file(tmp_path: Path, data: bytes, kind: str = "program") -> Path:
    suffix = {"program": ".nc", "measurements": ".csv", "trajectory": ".csv"}.get(kind, ".yaml")
    path = tmp_path / f"input{suffix}"
    path.write_bytes(data)
    return path


def _clean(err: str, *secrets: str) -> str:
    """Check an error line: one line, short, no traceback, no secret; return it."""
    assert err.endswith("\n") and err.count("\n") == 1, err[:2000]
    assert len(err) <= MAX_LINE, err[:2000]
    assert "Traceback" not in err
    assert not re.search(r"[\x00-\x08\x0b-\x1f\x7f]", err), err  # control characters escaped
    for secret in (MARK, *secrets):
        assert secret not in err, err
    return err


def _cli(capsys: pytest.CaptureFixture[str], kind: str, path: Path, *secrets: str) -> str:
    argv, _ = READERS[kind]
    if not argv:
        return ""
    code, out, err = run(capsys, *(a.format(path) for a in argv))
    assert (code, out) == (ERROR, "")
    assert err.startswith(f"orthoglide {argv[0]}: error: "), err
    return _clean(err, *secrets)


def _api(kind: str, path: Path, *secrets: str) -> str:
    with pytest.raises(OrthoglideError) as info:
        READERS[kind][1](path)
    return _clean(f"{info.value}\n", *secrets)


def _both(capsys: pytest.CaptureFixture[str], kind: str, path: Path, *needles: str) -> None:
    for message in (_cli(capsys, kind, path), _api(kind, path)):
        for needle in needles:
            assert not message or needle in message, message


# ------------------------------------------------------------ not text
@pytest.mark.parametrize("kind", sorted(READERS))
def test_a_nul_byte_is_not_text_named_by_its_offset(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, kind: str
) -> None:
    head = f"a: 1\n{MARK}".encode()
    path = _file(tmp_path, head + b"\0" + MARK.encode() + b"\n", kind)
    _both(capsys, kind, path, "not a text file", f"a NUL byte at offset {len(head)}")


@pytest.mark.parametrize("kind", sorted(READERS))
def test_latin1_is_not_text_named_by_its_offset(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, kind: str
) -> None:
    head = f"a: 1 # {MARK} longueur mesur".encode()
    path = _file(tmp_path, head + "ée\n".encode("latin-1"), kind)
    _both(capsys, kind, path, "not a text file", f"not UTF-8 at offset {len(head)}")


def test_the_environment_behind_a_link_is_never_shown(tmp_path: Path) -> None:
    (tmp_path / "job.nc").symlink_to("/proc/self/environ")
    (tmp_path / "job.yaml").symlink_to("/proc/self/environ")
    env = {**os.environ, "ORTHOGLIDE_TEST_SECRET": MARK}
    for argv in (
        ("plan", "job.nc", "--out", "out", "--max-slider-acceleration", "20"),
        ("ik", "0", "0", "0", "--config", "job.yaml"),
    ):
        done = subprocess.run(
            [ORTHOGLIDE, *argv],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
            check=False,
        )
        assert (done.returncode, done.stdout) == (ERROR, ""), done.stderr[:2000]
        err = _clean(done.stderr, "PATH=", os.environ.get("HOME", MARK))
        assert "(it is not a text file: a NUL byte at offset" in err
    assert not (tmp_path / "out").exists()


def test_a_password_file_shows_at_most_its_first_word(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    lines = f"root:x:0:0:{MARK}:/root:/bin/bash\nuser:x:1000:1000:{MARK}2:/home/user:/bin/sh\n"
    target = tmp_path / "passwd"
    target.write_text(lines)
    (tmp_path / "job.nc").symlink_to(target)
    err = _cli(capsys, "program", tmp_path / "job.nc", ":x:0:0:", "/bin/bash", "user")
    assert err.startswith("orthoglide plan: error: program line 1: ")
    assert "unreadable word 'root' at column 1 (a word is a letter then a number)" in err
    if Path("/etc/passwd").is_file():
        code, _, err = run(capsys, "plan", "/etc/passwd", "--out", str(tmp_path / "o"))
        assert code == ERROR and ":x:0:0:" not in _clean(err)


def test_proc_files_are_read_up_to_the_cap(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    code, _, err = run(capsys, "plan", "/proc/self/status", "--out", str(tmp_path / "never"))
    assert code == ERROR and "Tgid" not in _clean(err) and "(running)" not in err
    with pytest.raises(og.InvalidParameterError, match="it has more, though it reports no size"):
        _io.read_input_bytes("/proc/self/maps", "maps", 16)  # stats as an empty file


# ------------------------------------------------------------ long values
def test_a_huge_word_gives_a_short_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = _file(tmp_path, b"G1 " + b"Q" * HUGE + MARK.encode() + b"\n")
    _both(capsys, "program", path, f"({HUGE + len(MARK)} characters)", "unreadable word 'QQQ")
    path.write_text(f"G1 X1 F100\nG1 X1,{'Q' * HUGE}{MARK} Y2\n")
    _both(capsys, "program", path, "line 2: unreadable character ',' at column 6")
    path.write_text(f"G1 X1 F100\nG1 Q{'9' * HUGE}\n")
    _both(capsys, "program", path, f"unsupported word Q{'9' * 20}", f"({HUGE} digits)")


@pytest.mark.parametrize(
    ("kind", "text"),
    [
        ("config", "leg_length: {}\n"),
        ("config", "{}: 0.3\n"),
        ("motor file", "drive_train:\n  {}: 1\n"),
        ("calibration", "format: {}\n"),
        ("measurements", "q1,q2,q3,{}\n"),
        ("trajectory", "t,x,y,z,{}\n0,0,0,0,0\n"),
        ("trajectory", "t,x,y,z,path_speed\n0,0,0,0,{}\n"),
        ("loop data", "closures: [{}]\n"),
    ],
)
def test_a_long_value_is_cut_to_80_characters(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, kind: str, text: str
) -> None:
    value = "v" * (MAX_VALUE_CHARS + 10) + MARK + "\x1b[31m" + "w" * LONG
    path = _file(tmp_path, text.format(value).encode(), kind)
    for message in (_cli(capsys, kind, path), _api(kind, path)):
        shown = ("v" * 10, "characters", "field limit (131072)")  # the csv module's limit
        assert not message or any(part in message for part in shown), message


def test_a_control_character_is_escaped(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = _file(tmp_path, b'leg_length: "a\\e[31mb\\nc"\n', "config")
    for message in (_cli(capsys, "config", path), _api("config", path)):
        assert "\x1b" not in message and r"'a\x1b[31mb\nc'" in message, message


def test_a_yaml_error_quotes_no_snippet(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = _file(tmp_path, f"a: [1, 2\nb: {MARK}\n".encode(), "config")
    _both(capsys, "config", path, "expected valid YAML", "at line")
    path.write_text(f"- {MARK}\n")
    _both(capsys, "config", path, "a mapping of names to values (it is a list)")


# ------------------------------------------------------------ sizes
def test_a_size_is_checked_before_reading(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "big.nc"
    with path.open("wb") as fh:  # sparse: no disk used
        fh.truncate(MAX_PROGRAM_BYTES + 1)

    def never(*_: object) -> bytes:
        raise AssertionError("a file larger than the cap was read")

    monkeypatch.setattr(_io.os, "read", never)
    allowed = f"a file of at most {MAX_PROGRAM_BYTES} bytes (it has "
    _both(capsys, "program", path, allowed)
    config = tmp_path / "big.yaml"
    with config.open("wb") as fh:
        fh.truncate(_io.MAX_INPUT_BYTES + 1)
    _both(capsys, "config", config, f"at most {_io.MAX_INPUT_BYTES} bytes")


@pytest.mark.parametrize("kind", ["program", "config", "measurements"])
def test_a_fifo_or_a_directory_is_refused_without_reading(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, kind: str
) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    _both(capsys, kind, fifo, "a regular file (it is a named pipe (FIFO))")
    folder = tmp_path / "folder"
    folder.mkdir()
    _both(capsys, kind, folder, "a readable file (it is a directory)")


# ------------------------------------------------------------ the API's text
def test_the_api_refuses_a_nul_in_a_program_or_a_config() -> None:
    with pytest.raises(og.InvalidParameterError, match="a NUL character at offset 9") as info:
        og.read_program(f"G1 X1 F1\n\0{MARK}")
    assert MARK not in str(info.value)
    with pytest.raises(og.InvalidParameterError, match="a NUL character at offset 5") as info:
        og.OrthoglideParams.from_yaml(f"a: 1\n\0{MARK}")
    assert MARK not in str(info.value)
    with pytest.raises(og.CalibrationError, match="a NUL byte at offset 3") as error:
        og.parse_measurements(f"q1,\0{MARK}".encode())
    assert MARK not in str(error.value)


# ------------------------------------------------------------ the one place that shows values
def test_short_repr_escapes_and_cuts() -> None:
    from orthoglide_pin.exceptions import MAX_PATH_CHARS, one_line, short_repr

    assert short_repr("a\x00\n\x1b[31m\u2028b") == r"'a\x00\n\x1b[31m\u2028b'"
    cut = short_repr("z" * HUGE)
    assert len(cut) <= MAX_VALUE_CHARS + len(f" ({HUGE} characters)") and cut.endswith(
        f"... ({HUGE} characters)"
    )
    long_path = Path("/data/" + "d" * 1000 + "/job.nc")
    shown = short_repr(long_path)
    assert shown.startswith("'/data/ddd") and "ddd/job.nc'" in shown
    assert len(shown) <= MAX_PATH_CHARS + len(" (1011 characters)")
    assert one_line("a\nb\tc\x1b") == r"a\nb\tc\x1b"
    message = str(og.InvalidParameterError("x" * 1000, "v", "anything"))
    assert len(message) < 200 and "\n" not in message


# ------------------------------------------------------------ a Parquet trajectory
@pytest.mark.parametrize(
    "data",
    [MARK.encode() + b"\nt,x,y,z,path_speed\n", b"PAR1" + MARK.encode() + b"PAR1", b""],
    ids=["text", "magic-only", "empty"],
)
def test_a_parquet_suffix_on_another_file_is_refused_in_one_line(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, data: bytes
) -> None:
    pytest.importorskip("pyarrow.parquet")
    path = tmp_path / "trajectory.parquet"
    path.write_bytes(data)
    argv = ("view", "--trajectory", str(path), "--static", str(tmp_path / "v.html"))
    code, out, err = run(capsys, *argv)
    assert (code, out) == (ERROR, "") and not (tmp_path / "v.html").exists()
    assert "not a Parquet file" in _clean(err)
    with pytest.raises(og.InvalidParameterError, match="not a Parquet file"):
        read_trajectory(path, og.OrthoglideParams())


def test_a_parquet_trajectory_over_the_size_cap_is_refused_before_it_is_read(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    pytest.importorskip("pyarrow.parquet")
    path = tmp_path / "trajectory.parquet"
    path.write_bytes(b"PAR1" + b"\0" * 2000 + b"PAR1")
    monkeypatch.setattr("orthoglide_pin.viewer.planned.MAX_TRAJECTORY_BYTES", 1000)
    with pytest.raises(og.InvalidParameterError, match="1000"):
        read_trajectory(path, og.OrthoglideParams())
