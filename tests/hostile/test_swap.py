"""The swap of a directory written whole removes only what the package wrote.

``report --out`` and ``urdf --package-dir`` replace their directory whole when
everything in it is theirs; any entry the package did not write, a directory
named like one of its files included, is refused with nothing removed.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import run
from hostile.test_outputs import FAST_REPORT, fill, one_error_line, snapshot

from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin._paths import MARKER_NAME, TEMP_TAG
from orthoglide_pin.exceptions import OutputPathError


def _no_temporaries(root: Path) -> None:
    assert not [p for p in root.rglob("*") if TEMP_TAG in p.name]


# ------------------------------------------------------------ the whole-directory swap
def test_a_directory_named_like_a_file_of_ours_is_never_swapped_away(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1", "b.txt": "1"})
    (target / "b.txt").unlink()
    (target / "b.txt").mkdir()  # the user's own directory, under one of our names
    (target / "b.txt" / "data.csv").write_text("mine")
    before = snapshot(tmp_path)
    with (
        pytest.raises(OutputPathError, match=r"a directory named 'b\.txt'"),
        atomic_directory(target) as tmp,
    ):
        fill(tmp, {"a.txt": "2", "b.txt": "2"})
    assert snapshot(tmp_path) == before  # nothing written, nothing removed
    _no_temporaries(tmp_path)


def test_what_the_user_put_in_a_directory_of_ours_is_never_swapped_away(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1"})
        (tmp / "deep").mkdir()
        fill(tmp / "deep", {"b.txt": "1"})
    (target / "deep" / "mine.txt").write_text("mine")
    before = snapshot(tmp_path)
    with (
        pytest.raises(OutputPathError, match="directory named 'deep'"),
        atomic_directory(target) as tmp,
    ):
        fill(tmp, {"a.txt": "2"})
        (tmp / "deep").mkdir()
    assert snapshot(tmp_path) == before
    _no_temporaries(tmp_path)
    (target / "deep" / "mine.txt").unlink()  # all ours again: swapped whole
    inode = target.stat().st_ino
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "3"})
        (tmp / "deep").mkdir()
    assert target.stat().st_ino != inode
    assert {k: v for k, v in snapshot(target).items() if k != MARKER_NAME} == {
        "a.txt": b"3",
        "deep": None,
    }


def test_a_file_the_marker_does_not_list_is_not_replaced_unless_forced(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with atomic_directory(target) as tmp:
        fill(tmp, {"a.txt": "1"})
    (target / "b.txt").write_text("the user's")  # a name the next run writes
    before = snapshot(tmp_path)
    with (
        pytest.raises(OutputPathError, match=r"'b\.txt' that orthoglide-pin did not write"),
        atomic_directory(target) as tmp,
    ):
        fill(tmp, {"a.txt": "2", "b.txt": "2"})
    assert snapshot(tmp_path) == before
    with atomic_directory(target, force=True) as tmp:  # forced: replaced, as documented
        fill(tmp, {"a.txt": "2", "b.txt": "2"})
    assert (target / "b.txt").read_text() == "2"


def test_report_keeps_a_directory_named_like_a_report_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "report"
    code, _, err = run(capsys, "report", "--out", str(out), *FAST_REPORT)
    assert code == 0, err
    (out / "maps.csv").unlink()
    (out / "maps.csv").mkdir()
    (out / "maps.csv" / "my-measurements.csv").write_text("x,y\n1,2\n")
    before = snapshot(tmp_path)
    for force in ((), ("--force",)):  # a directory in the way, even forced
        code, stdout, err = run(capsys, "report", "--out", str(out), *FAST_REPORT, *force)
        one_error_line(code, stdout, err, str(out), "'maps.csv'", "directory")
        assert snapshot(tmp_path) == before


def test_urdf_package_dir_keeps_a_directory_named_like_its_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "pkg"
    assert run(capsys, "urdf", "--package-dir", str(out))[0] == 0
    (out / "orthoglide.loops.yaml").unlink()
    (out / "orthoglide.loops.yaml").mkdir()
    (out / "orthoglide.loops.yaml" / "notes.txt").write_text("mine")
    before = snapshot(tmp_path)
    for force in ((), ("--force",)):
        code, stdout, err = run(capsys, "urdf", "--package-dir", str(out), *force)
        one_error_line(code, stdout, err, str(out), "'orthoglide.loops.yaml'")
        assert snapshot(tmp_path) == before
    _no_temporaries(tmp_path)
