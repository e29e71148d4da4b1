"""Outputs never lose data: marked report directories, special files, temporary files."""

from __future__ import annotations

import json
import os
import re
import stat
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from conftest import run

from orthoglide_pin import _io, _paths
from orthoglide_pin._io import atomic_write_text
from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin._paths import MARKER_NAME, TEMP_TAG, remove_stale_temps
from orthoglide_pin.exceptions import OutputPathError

#: Exit status of every error.
ERROR = 2
#: Small report grids: the report command in a few seconds.
FAST_REPORT = ("--quiet", "--resolution", "5", "--cube-resolution", "5")
#: Files of a report directory.
REPORT_FILES = {
    "report.html",
    "report.json",
    "summary.csv",
    "maps.csv",
    "cube.csv",
    "cycle.csv",
    "vibration.csv",
    MARKER_NAME,
}

#: A quick design command (its --write-config is an atomic write).
DESIGN = ("design", "--workspace", "0.2", "--psi", "0.5", "2", "--grid", "3")

Cli = Callable[..., subprocess.CompletedProcess[str]]


def snapshot(root: Path) -> dict[str, bytes | None]:
    """Every path under ``root`` and the bytes of its files."""
    return {
        str(p.relative_to(root)): (p.read_bytes() if p.is_file() else None)
        for p in sorted(root.rglob("*"))
    }


def one_error_line(code: int, out: str, err: str, *mentions: str) -> None:
    assert code == ERROR, err
    assert out == ""
    assert err.count("\n") == 1 and re.match(r"orthoglide [a-z]+: error: ", err), err
    for text in mentions:
        assert text in err, err
    assert TEMP_TAG not in err and ".tmp" not in err  # never a temporary file's name


def user_files(root: Path) -> dict[str, bytes | None]:
    (root / "notes.txt").write_text("my notes")
    (root / "data").mkdir()
    (root / "data" / "run1.csv").write_text("1,2,3\n")
    return snapshot(root)


# ------------------------------------------------------------ report --out
@pytest.mark.parametrize("out", ["mine", ".", ""])
def test_report_refuses_a_directory_it_did_not_write(
    capsys: pytest.CaptureFixture[str],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    out: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine").mkdir()
    before = user_files(tmp_path / "mine" if out == "mine" else tmp_path)
    whole = snapshot(tmp_path)
    code, stdout, err = run(capsys, "report", "--out", out, "--quiet")
    if out:
        one_error_line(code, stdout, err, f"'{out}'")
    else:  # refused with the other path options, by the argument parser
        assert (code, stdout) == (ERROR, "") and err.count("\n") == 1
        assert err.startswith("orthoglide report: error: argument --out: an empty path")
    assert snapshot(tmp_path) == whole  # nothing written, nothing removed
    assert before  # the user's files were there, and still are
    assert "--force" in err or out == ""


def test_report_refuses_a_file_in_the_way(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    target = tmp_path / "report"
    target.write_text("not a directory")
    one_error_line(*run(capsys, "report", "--out", str(target), "--quiet"), "not a directory")
    assert target.read_text() == "not a directory"


def test_report_force_keeps_every_other_file(cli: Cli, tmp_path: Path) -> None:
    mine = tmp_path / "mine"
    mine.mkdir()
    before = user_files(mine)
    done = cli("report", "--out", "mine", "--force", *FAST_REPORT)
    assert done.returncode == 0, done.stderr
    after = snapshot(mine)
    assert {k: after[k] for k in before} == before  # the user's files, untouched
    assert set(after) - set(before) == REPORT_FILES
    listed = (mine / MARKER_NAME).read_text().splitlines()[1:]
    assert set(listed) == REPORT_FILES - {MARKER_NAME}
    assert not [p for p in tmp_path.iterdir() if TEMP_TAG in p.name]


# ------------------------------------------------------------ owned directories
def fill(tmp: Path, names: dict[str, str]) -> None:
    for name, text in names.items():
        (tmp / name).write_text(text)


def test_a_pure_report_directory_is_replaced_whole(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1", "b.txt": "1"})
    inode = target.stat().st_ino
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "2", "b.txt": "2"})
    assert target.stat().st_ino != inode  # swapped: readers see one report or the other
    assert {k: v for k, v in snapshot(target).items() if k != MARKER_NAME} == {
        "a.txt": b"2",
        "b.txt": b"2",
    }
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_a_report_into_a_sweep_directory_keeps_the_sweep(tmp_path: Path) -> None:
    from orthoglide_pin._outdir import claim_directory

    sweep = claim_directory(tmp_path / "sw", ["results.csv", "parts"])
    (sweep / "results.csv").write_text("L,torque\n")
    (sweep / "parts").mkdir()
    with atomic_directory(sweep) as tmp:  # marked: allowed without force
        fill(tmp, {"report.html": "r"})
    assert (sweep / "results.csv").read_text() == "L,torque\n"
    listed = (sweep / MARKER_NAME).read_text().splitlines()[1:]
    assert listed == ["parts", "report.html", "results.csv"]


def test_a_marked_directory_keeps_what_the_user_added(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1", "b.txt": "1"})
    (target / "notes.txt").write_text("mine")
    inode = target.stat().st_ino
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "2"})
    assert (target / "notes.txt").read_text() == "mine"
    assert (target / "a.txt").read_text() == "2"
    assert (target / "b.txt").read_text() == "1"  # an earlier file of ours: kept, still listed
    assert target.stat().st_ino == inode  # written into, not swapped
    listed = (target / MARKER_NAME).read_text().splitlines()[1:]
    assert listed == ["a.txt", "b.txt"]  # notes.txt is never claimed


def test_the_working_directory_is_never_swapped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1"})
    monkeypatch.chdir(target)
    inode = target.stat().st_ino
    with atomic_directory(".") as tmp:
        fill(tmp, {"a.txt": "2"})
    assert target.stat().st_ino == inode and Path.cwd().samefile(target)
    assert (target / "a.txt").read_text() == "2"


def test_a_directory_that_changes_during_the_work_is_refused_at_the_end(
    tmp_path: Path,
) -> None:
    target = tmp_path / "out"
    target.mkdir()  # empty: allowed at the start
    refused = pytest.raises(OutputPathError, match="not written by orthoglide-pin")
    with refused, atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1"})
        (target / "notes.txt").write_text("written meanwhile")
    assert snapshot(target) == {"notes.txt": b"written meanwhile"}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary left


def test_an_unwritable_parent_writes_file_by_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import tempfile

    from orthoglide_pin import _outdir

    home = tmp_path / "home"
    home.mkdir()
    before = user_files(home)
    real = tempfile.mkdtemp
    refusing: list[Path] = [tmp_path]  # a parent that refuses, as /home does a user

    def no_sibling(*args: Any, **kwargs: Any) -> str:
        if Path(kwargs["dir"]) in refusing:
            raise PermissionError(13, "Permission denied", str(kwargs["dir"]))
        return real(*args, **kwargs)

    monkeypatch.setattr(_outdir.tempfile, "mkdtemp", no_sibling)
    monkeypatch.chdir(home)
    with atomic_directory(".", force=True) as tmp:
        assert tmp.parent == home
        fill(tmp, {"report.html": "r"})
    after = snapshot(home)
    assert {k: after[k] for k in before} == before
    assert set(after) - set(before) == {"report.html", MARKER_NAME}
    # an empty directory is still accepted: the temporary inside it does not count
    empty = home / "empty"
    empty.mkdir()
    refusing.append(home)
    with atomic_directory(empty) as tmp:
        assert tmp.parent == empty
        fill(tmp, {"report.html": "r"})
    assert {p.name for p in empty.iterdir()} == {"report.html", MARKER_NAME}


def test_forced_writes_never_replace_a_special_file_or_a_directory(tmp_path: Path) -> None:
    target = tmp_path / "mine"
    target.mkdir()
    os.mkfifo(target / "report.html")
    (target / "report.json").mkdir()
    (target / "report.json" / "inside.txt").write_text("mine")
    before = snapshot(target)
    for name in ("report.html", "report.json"):
        with (
            pytest.raises(OutputPathError, match=f"named '{name}'"),
            atomic_directory(target, force=True) as tmp,
        ):
            fill(tmp, {name: "ours", "cube.csv": "1"})
        assert snapshot(target) == before  # not even cube.csv: nothing half installed
    assert stat.S_ISFIFO((target / "report.html").lstat().st_mode)
    assert [p.name for p in tmp_path.iterdir()] == ["mine"]


def test_a_link_to_a_directory_is_written_through(tmp_path: Path) -> None:
    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "link"
    link.symlink_to(real)
    with atomic_directory(link) as tmp:
        fill(tmp, {"a.txt": "1"})
    assert link.is_symlink() and (real / "a.txt").read_text() == "1"


# ------------------------------------------------------------ special files
def special_files(tmp_path: Path) -> dict[str, Path]:
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    found = {"fifo": fifo}
    device = tmp_path / "null-device"
    try:  # a private copy of /dev/null: the real one is never at risk
        os.mknod(device, stat.S_IFCHR | 0o666, os.makedev(1, 3))
        found["device"] = device
    except (PermissionError, OSError):
        pass
    return found


@pytest.mark.parametrize(
    "command",
    [
        ["urdf", "-o", "{path}"],
        [
            "design",
            "--workspace",
            "0.2",
            "--psi",
            "0.5",
            "2",
            "--grid",
            "3",
            "--write-config",
            "{path}",
        ],
        ["map", "--resolution", "5", "--out", "{path}"],
        ["map", "--resolution", "5", "--out", "{tmp}/m.png", "--csv", "{path}"],
        ["view", "--static", "{path}"],
    ],
    ids=["urdf", "write-config", "map-png", "map-csv", "view-static"],
)
def test_commands_refuse_special_files(cli: Cli, tmp_path: Path, command: list[str]) -> None:
    for kind, path in special_files(tmp_path).items():
        argv = [a.format(path=path, tmp=tmp_path) for a in command]
        done = cli(*argv)  # a FIFO opened for writing would block: the timeout guards it
        one_error_line(done.returncode, done.stdout, done.stderr, str(path), "not a regular file")
        mode = path.lstat().st_mode
        assert stat.S_ISFIFO(mode) if kind == "fifo" else stat.S_ISCHR(mode), kind


def test_the_writers_refuse_special_files(tmp_path: Path) -> None:
    from orthoglide_pin.sweep.runner import write_tables

    for path in special_files(tmp_path).values():
        with pytest.raises(OutputPathError, match="not a regular file"):
            atomic_write_text(path, "x")
    out = tmp_path / "sweep"
    out.mkdir()
    os.mkfifo(out / "results.csv")
    import pandas as pd

    with pytest.raises(OutputPathError, match=r"results\.csv"):
        write_tables(out, pd.DataFrame({"a": [1.0]}))
    assert stat.S_ISFIFO((out / "results.csv").lstat().st_mode)
    assert not list(out.glob(f".*{TEMP_TAG}*"))


def test_dev_null_is_refused_and_untouched() -> None:
    before = os.lstat(os.devnull)
    with pytest.raises(OutputPathError, match="character device"):
        atomic_write_text(Path(os.devnull), "x")
    after = os.lstat(os.devnull)
    assert (after.st_ino, after.st_rdev) == (before.st_ino, before.st_rdev)


def test_a_link_to_a_file_is_written_through(tmp_path: Path) -> None:
    real = tmp_path / "real.txt"
    real.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(real)
    atomic_write_text(link, "new")
    assert link.is_symlink() and real.read_text() == "new"


# ------------------------------------------------------------ error messages
def test_errors_name_the_given_path_not_the_temporary_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def full(src: str, dst: str) -> None:
        raise OSError(28, "No space left on device", src, None, dst)

    monkeypatch.setattr(_io.os, "replace", full)
    given = str(tmp_path / "d.yaml")
    code, out, err = run(capsys, *DESIGN, "--write-config", given)
    one_error_line(code, out, err, given, "no space left on device")
    assert list(tmp_path.iterdir()) == []  # the temporary file is gone too


def test_a_directory_given_as_a_file(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    one_error_line(*run(capsys, "urdf", "-o", str(tmp_path)), str(tmp_path), "is a directory")


def test_an_empty_output_path() -> None:
    with pytest.raises(OutputPathError, match="an empty path"):
        atomic_write_text("", "x")
    with pytest.raises(OutputPathError, match="an empty path"), atomic_directory(""):
        pass


# ------------------------------------------------------------ temporary files
def dead_pid() -> int:
    """The id of a process that has exited (and been reaped)."""
    done = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    return int(done.stdout)


def test_stale_temporaries_are_removed_and_nothing_else(tmp_path: Path) -> None:
    dead, alive = dead_pid(), os.getppid()
    stale_file = tmp_path / f".a.urdf.{TEMP_TAG}-{dead}-x1y2.tmp"
    stale_file.write_text("half")
    stale_dir = tmp_path / f".report.{TEMP_TAG}-{dead}-k9.tmp"
    stale_dir.mkdir()
    (stale_dir / "report.html").write_text("half")
    old_dir = tmp_path / f".report.{TEMP_TAG}-{dead}-k8.old"
    (old_dir / "report").mkdir(parents=True)
    running = tmp_path / f".b.urdf.{TEMP_TAG}-{alive}-z.tmp"  # another run, still going
    running.write_text("in progress")
    ancient = tmp_path / f".c.urdf.{TEMP_TAG}-{alive}-w.tmp"
    ancient.write_text("two days old")
    two_days_ago = time.time() - 2 * 24 * 3600
    os.utime(ancient, (two_days_ago, two_days_ago))
    lookalikes = [tmp_path / ".a.urdf.tmp", tmp_path / f".notes.{TEMP_TAG}-x.tmp"]
    for path in lookalikes:
        path.write_text("the user's")
    atomic_write_text(tmp_path / "new.txt", "x")
    left = {p.name for p in tmp_path.iterdir()}
    assert left == {"new.txt", running.name, *(p.name for p in lookalikes)}
    # scanned once per directory and process, unless asked again
    stale_file.write_text("half")
    assert remove_stale_temps(tmp_path) == []
    assert remove_stale_temps(tmp_path, again=True) == [stale_file]


def test_temporary_names_carry_the_owner(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    seen: list[str] = []
    real = os.replace

    def spy(src: str, dst: str) -> None:
        seen.append(os.path.basename(src))
        real(src, dst)

    monkeypatch.setattr(_io.os, "replace", spy)
    atomic_write_text(tmp_path / "f.txt", "x")
    assert seen and seen[0].startswith(f".f.txt.{TEMP_TAG}-{os.getpid()}-")
    assert _paths.temp_prefix("f.txt") == f".f.txt.{TEMP_TAG}-{os.getpid()}-"


def test_a_failed_write_leaves_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def interrupted(*_: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(_io.os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        atomic_write_text(tmp_path / "f.txt", "x")
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------ sweep --out
SWEEP = ("sweep", "--leg-length", "0.3:0.31:2", "--workers", "1", "--grid", "5")
SWEEP_FAST = ("--requirement-grid", "3", "--no-plot", "--no-progress")


def test_sweep_refuses_a_directory_it_did_not_write(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "results.csv").write_text("my own table\n")
    whole = snapshot(tmp_path)
    one_error_line(*run(capsys, *SWEEP, *SWEEP_FAST, "--out", str(mine)), str(mine), "--force")
    assert snapshot(tmp_path) == whole


def test_sweep_carries_on_in_its_own_directory(cli: Cli, tmp_path: Path) -> None:
    first = cli(*SWEEP, *SWEEP_FAST, "--out", "sw")
    assert first.returncode == 0, first.stderr
    listed = (tmp_path / "sw" / MARKER_NAME).read_text().splitlines()[1:]
    assert {"sweep.json", "parts", "results.csv"} <= set(listed)
    (tmp_path / "sw" / MARKER_NAME).unlink()  # as written before the marker existed
    again = cli(*SWEEP, *SWEEP_FAST, "--out", "sw", "--json")
    assert again.returncode == 0, again.stderr
    assert json.loads(again.stdout)["skipped"] == 2
