"""The URDF caches: bounded, least recently used out first, shared safely, user files kept."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin.exceptions import OutputPathError
from orthoglide_pin.machine import urdf_cache
from orthoglide_pin.machine.description import cache_key

#: Entry cap of the tests (small, so that a few renderings reach it).
CAP = 3
#: Processes sharing one cache, and entries each writes.
WRITERS = 4
ENTRIES_EACH = 40
#: Seconds a writer process may take.
WRITER_TIMEOUT = 120.0
#: A point in the past for the modification times set by the tests [s since the epoch].
PAST = 1_600_000_000


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A fresh, empty cache directory with a cap of ``CAP`` entries and a fresh memory."""
    folder = tmp_path / "cache"
    monkeypatch.setenv(urdf_cache.CACHE_ENV, str(folder))
    monkeypatch.setattr(urdf_cache, "MAX_ENTRIES", CAP)
    urdf_cache.forget_all()
    yield folder
    urdf_cache.forget_all()


def _machines(n: int) -> list[og.OrthoglideParams]:
    """``n`` machines that differ (leg lengths of 0.30 m, 0.31 m, ...)."""
    return [og.prototype().replace(leg_length=0.30 + 0.01 * i) for i in range(n)]


def _entries(folder: Path) -> set[str]:
    return {p.name for p in folder.glob("orthoglide-*.urdf")}


def _name(params: og.OrthoglideParams) -> str:
    return f"orthoglide-{cache_key(params)}.urdf"


def _age(folder: Path, machines: list[og.OrthoglideParams]) -> None:
    """Give the entries of ``machines`` increasing times in the past (the first oldest)."""
    for i, params in enumerate(machines):
        os.utime(folder / _name(params), (PAST + i, PAST + i))


def test_the_least_recently_used_entry_goes_first(cache: Path) -> None:
    a, b, c, d = _machines(4)
    texts = {_name(m): og.render_urdf(m) for m in (a, b, c)}
    assert _entries(cache) == set(texts)
    _age(cache, [a, b, c])
    urdf_cache.forget_all()
    assert og.render_urdf(a) == texts[_name(a)]  # a hit on disk: a is now the newest
    og.render_urdf(d)
    assert _entries(cache) == {_name(a), _name(c), _name(d)}  # b, the oldest, is out
    urdf_cache.forget_all()
    assert og.render_urdf(b) == og.render_urdf(b, use_cache=False)  # rendered again, same
    assert _entries(cache) == {_name(a), _name(d), _name(b)}


def test_urdf_path_touches_its_entry(cache: Path) -> None:
    a, b, c, d = _machines(4)
    for m in (a, b, c):
        og.urdf_path(m)
    _age(cache, [a, b, c])
    path = og.urdf_path(a)  # a memory hit: the file is touched all the same
    assert path.stat().st_mtime > PAST + 10
    og.urdf_path(d)
    assert _entries(cache) == {_name(a), _name(c), _name(d)}
    assert path.is_file()


def test_the_byte_cap(cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    machines = _machines(4)
    size = len(og.render_urdf(machines[0], use_cache=False).encode())
    monkeypatch.setattr(urdf_cache, "MAX_ENTRIES", 100)
    monkeypatch.setattr(urdf_cache, "MAX_BYTES", int(2.5 * size))
    for m in machines:
        og.render_urdf(m)
    assert _entries(cache) == {_name(m) for m in machines[2:]}
    assert sum(p.stat().st_size for p in cache.glob("orthoglide-*.urdf")) <= 2.5 * size


def test_nothing_the_package_did_not_write_is_removed(cache: Path, tmp_path: Path) -> None:
    cache.mkdir()
    elsewhere = tmp_path / "elsewhere.urdf"
    elsewhere.write_text('<?xml version="1.0" ?>\n<robot name="orthoglide"/>\n')
    foreign = {
        "notes.txt": "my notes",
        f"orthoglide-{'a' * 32}.urdf": "my own file, named like an entry",
        f"orthoglide-{'b' * 32}.urdf.bak": '<?xml version="1.0" ?><robot name="orthoglide"/>',
        f"orthoglide-{'c' * 31}.urdf": '<?xml version="1.0" ?><robot name="orthoglide"/>',
    }
    for name, text in foreign.items():
        (cache / name).write_text(text)
    (cache / f"orthoglide-{'d' * 32}.urdf").symlink_to(elsewhere)
    (cache / f"orthoglide-{'e' * 32}.urdf").mkdir()
    for path in cache.iterdir():
        os.utime(path, (PAST, PAST), follow_symlinks=False)  # older than any entry
    machines = _machines(CAP + 2)
    for m in machines:
        og.render_urdf(m)
    for name, text in foreign.items():
        assert (cache / name).read_text() == text
    assert (cache / f"orthoglide-{'d' * 32}.urdf").is_symlink() and elsewhere.is_file()
    assert (cache / f"orthoglide-{'e' * 32}.urdf").is_dir()
    ours = {_name(m) for m in machines}
    assert _entries(cache) & ours == {_name(m) for m in machines[-CAP:]}


def test_a_read_only_cache_still_renders(cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    a, b = _machines(2)
    og.render_urdf(a)
    before = {p.name: p.read_bytes() for p in cache.iterdir()}

    def refused(path: object, *_: object) -> None:
        raise OutputPathError(path, "permission denied")

    def no_utime(*_: object, **__: object) -> None:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(urdf_cache, "atomic_write_text", refused)  # as a read-only folder
    monkeypatch.setattr(urdf_cache.os, "utime", no_utime)
    urdf_cache.forget_all()
    assert og.render_urdf(b) == og.render_urdf(b, use_cache=False)  # not stored, no error
    assert og.render_urdf(a) == og.render_urdf(a, use_cache=False)  # read, not touched
    assert {p.name: p.read_bytes() for p in cache.iterdir()} == before
    with pytest.raises(og.DescriptionError, match="cannot write URDF cache"):
        og.urdf_path(b)  # a path needs the file


def test_the_memory_cache_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(urdf_cache, "MEMORY_ENTRIES", 2)
    urdf_cache.forget_all()
    for key in ("k1", "k2"):
        urdf_cache.remember(key, key)
    assert urdf_cache.remembered("k1") == "k1"  # k1 is now the newest
    urdf_cache.remember("k3", "k3")
    assert urdf_cache.memory_keys() == ["k1", "k3"]
    assert urdf_cache.remembered("k2") is None
    urdf_cache.forget_all()


_WRITER = textwrap.dedent(
    """
    import sys
    from orthoglide_pin.machine import urdf_cache

    urdf_cache.MAX_ENTRIES = int(sys.argv[1])
    text = open(sys.argv[2], encoding="utf-8").read()
    me, each = int(sys.argv[3]), int(sys.argv[4])
    for i in range(each):
        key = f"{me:02x}{i:030x}"
        urdf_cache.store(key, text)
        for back in range(max(0, i - 3), i):  # read back recent ones: hits touch them
            got = urdf_cache.read(f"{me:02x}{back:030x}")
            assert got is None or got == text
    """
)


def test_concurrent_processes_keep_the_cap(cache: Path) -> None:
    cache.mkdir()
    (cache / "notes.txt").write_text("mine")
    sample = og.prototype_urdf_path()
    env = {**os.environ, urdf_cache.CACHE_ENV: str(cache)}
    writers = [
        subprocess.Popen(
            [sys.executable, "-c", _WRITER, str(CAP), str(sample), str(me), str(ENTRIES_EACH)],
            env=env,
            stderr=subprocess.PIPE,
            text=True,
        )
        for me in range(WRITERS)
    ]
    for writer in writers:
        _, err = writer.communicate(timeout=WRITER_TIMEOUT)
        assert writer.returncode == 0, err
    left = sorted(cache.glob("orthoglide-*.urdf"))
    assert len(left) == CAP  # every writer done: exactly the cap
    assert all(p.read_text() == sample.read_text() for p in left)  # whole entries only
    assert (cache / "notes.txt").read_text() == "mine"
    assert not [p for p in cache.iterdir() if p.name.endswith(".tmp")]
