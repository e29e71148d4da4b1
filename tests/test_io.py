"""Atomic output: files and whole directories appear complete or not at all."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from orthoglide_pin import _io
from orthoglide_pin._io import atomic_write_bytes, atomic_write_text, current_umask
from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin._paths import MARKER_NAME
from orthoglide_pin.exceptions import OutputPathError


@pytest.fixture
def umask() -> Iterator[None]:
    """Restores the process umask after a test that sets it."""
    old = os.umask(0o022)
    try:
        yield
    finally:
        os.umask(old)


def _mode(path: Path) -> int:
    return path.stat().st_mode & 0o777


def test_atomic_write_text(tmp_path: Path) -> None:
    path = tmp_path / "sub" / "file.txt"
    atomic_write_text(path, "one")
    atomic_write_text(path, "two")
    assert path.read_text() == "two"
    assert sorted(p.name for p in path.parent.iterdir()) == ["file.txt"]


def test_directory_appears_whole(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        assert tmp.parent == tmp_path and tmp != target
        (tmp / "a.txt").write_text("a")
        (tmp / "deep").mkdir()
        (tmp / "deep" / "b.txt").write_text("b")
        assert not target.exists()  # nothing visible before the end
    assert (target / "a.txt").read_text() == "a" and (target / "deep" / "b.txt").read_text() == "b"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert _mode(target) == 0o777 & ~current_umask()
    # the marker lists the names, then what is below each directory
    assert (target / MARKER_NAME).read_text().splitlines()[1:] == [
        "a.txt",
        "deep",
        "deep/",
        "deep/b.txt",
    ]
    # a second run replaces it whole when that loses nothing ...
    with atomic_directory(target) as tmp:
        (tmp / "a.txt").write_text("A")
        (tmp / "deep").mkdir()
    assert {p.name for p in target.iterdir()} == {"a.txt", "deep", MARKER_NAME}
    assert (target / "a.txt").read_text() == "A" and not list((target / "deep").iterdir())
    # ... else it adds its files and keeps the others, the earlier run's too
    with atomic_directory(target) as tmp:
        (tmp / "c.txt").write_text("c")
    assert {p.name for p in target.iterdir()} == {"a.txt", "c.txt", "deep", MARKER_NAME}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    listed = (target / MARKER_NAME).read_text().splitlines()[1:]
    assert listed == ["a.txt", "c.txt", "deep", "deep/"]  # the earlier directory, still ours


def test_failures_leave_the_previous_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        (tmp / "old.txt").write_text("old")
    with pytest.raises(KeyboardInterrupt), atomic_directory(target) as tmp:
        (tmp / "half.txt").write_text("ha")
        raise KeyboardInterrupt
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert {p.name for p in target.iterdir()} == {"old.txt", MARKER_NAME}
    # the swap itself fails after the old directory was moved aside: it comes back
    calls: list[Any] = []
    real = os.replace

    def flaky(src: Any, dst: Any) -> None:
        calls.append((src, dst))
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        real(src, dst)

    monkeypatch.setattr(_io.os, "replace", flaky)
    with pytest.raises(OSError), atomic_directory(target) as tmp:
        (tmp / "old.txt").write_text("new")
    assert len(calls) == 3  # aside, failed swap, back
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert (target / "old.txt").read_text() == "old"
    (tmp_path / "file").write_text("x")
    with (
        pytest.raises(OutputPathError, match="not a directory"),
        atomic_directory(tmp_path / "file"),
    ):
        pass


@pytest.mark.usefixtures("umask")
@pytest.mark.parametrize(
    ("mask", "file_mode", "dir_mode"),
    [(0o022, 0o644, 0o755), (0o027, 0o640, 0o750), (0o077, 0o600, 0o700)],
)
def test_written_files_follow_the_umask(
    tmp_path: Path, mask: int, file_mode: int, dir_mode: int
) -> None:
    os.umask(mask)
    assert current_umask() == mask
    atomic_write_text(tmp_path / "a.txt", "a")
    atomic_write_bytes(tmp_path / "b.bin", b"b")
    with atomic_directory(tmp_path / "out") as tmp:
        atomic_write_text(tmp / "inner.txt", "c")
        (tmp / "plain.txt").write_text("d")
    assert _mode(tmp_path / "a.txt") == _mode(tmp_path / "b.bin") == file_mode
    assert _mode(tmp_path / "out") == dir_mode
    assert _mode(tmp_path / "out" / "inner.txt") == _mode(tmp_path / "out" / "plain.txt")
    assert _mode(tmp_path / "out" / "inner.txt") == file_mode


@pytest.mark.usefixtures("umask")
def test_a_replaced_file_keeps_its_mode(tmp_path: Path) -> None:
    os.umask(0o022)
    for mode in (0o600, 0o664, 0o755):
        path = tmp_path / f"{mode:o}.txt"
        path.write_text("old")
        path.chmod(mode)
        atomic_write_text(path, "new")
        assert path.read_text() == "new"
        assert _mode(path) == mode


@pytest.mark.usefixtures("umask")
def test_umask_without_proc(monkeypatch: pytest.MonkeyPatch) -> None:
    os.umask(0o027)
    real_open = open

    def no_proc(file: object, *args: object, **kwargs: object) -> object:
        if str(file).startswith("/proc"):
            raise FileNotFoundError(2, "no /proc", str(file))
        return real_open(file, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr("builtins.open", no_proc)
    assert current_umask() == 0o027
    assert os.umask(0o022) == 0o027  # left as it was
