"""Atomic output: files and whole directories appear complete or not at all."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest

from orthoglide_pin import _io
from orthoglide_pin._io import atomic_directory, atomic_write_text


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
    assert target.stat().st_mode & 0o777 == 0o755
    # a second run replaces it whole
    with atomic_directory(target) as tmp:
        (tmp / "c.txt").write_text("c")
    assert sorted(p.name for p in target.iterdir()) == ["c.txt"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_failures_leave_the_previous_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out"
    target.mkdir()
    (target / "old.txt").write_text("old")
    with pytest.raises(KeyboardInterrupt), atomic_directory(target) as tmp:
        (tmp / "half.txt").write_text("ha")
        raise KeyboardInterrupt
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert [p.name for p in target.iterdir()] == ["old.txt"]
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
        (tmp / "new.txt").write_text("new")
    assert len(calls) == 3  # aside, failed swap, back
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert (target / "old.txt").read_text() == "old"
    (tmp_path / "file").write_text("x")
    with pytest.raises(NotADirectoryError), atomic_directory(tmp_path / "file"):
        pass
