"""Cost of keeping the URDF cache bounded: the eviction scan of a full cache against a rendering.

Every new cache entry lists the cache directory and evicts the oldest entries
beyond :data:`~orthoglide_pin.machine.urdf_cache.MAX_ENTRIES`; a sweep larger
than the cap does so for every design. This prints the time of that scan on a
full cache, of a store (atomic write, fsync and scan), and of the xacro
rendering that each design costs anyway, with their ratios (the scan should be
a few percent of a rendering).

Run from the repository root: ``PYTHONPATH=. python benchmarks/bench_urdf_cache.py``.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

from _timing import best_per_call, emit, parse_args

import orthoglide_pin as og
from orthoglide_pin.machine import urdf_cache

#: Scans and stores timed, and renderings.
CALLS = 20
RENDERINGS = 3


def bench_urdf_cache() -> dict[str, Any]:
    """Seconds of an eviction scan, a store and a rendering, and their ratios."""
    folder = Path(tempfile.mkdtemp(prefix="bench-urdf-cache-"))
    old = os.environ.get(urdf_cache.CACHE_ENV)
    os.environ[urdf_cache.CACHE_ENV] = str(folder)
    try:
        text = og.prototype_urdf_path().read_text()
        for i in range(urdf_cache.MAX_ENTRIES):
            (folder / f"orthoglide-{i:032x}.urdf").write_text(text)
        scan = best_per_call(lambda: urdf_cache.evict(folder), CALLS)
        counter = iter(range(10**9))
        store = best_per_call(
            lambda: urdf_cache.store(f"{next(counter) + 10**6:032x}", text), CALLS
        )
        machines = iter(og.prototype().replace(leg_length=0.3 + 1e-4 * i) for i in range(99))
        render = best_per_call(
            lambda: og.render_urdf(next(machines), use_cache=False), RENDERINGS, repeats=1
        )
        left = list(folder.glob("orthoglide-*.urdf"))
        result = {
            "entries": len(left),
            "megabytes": sum(p.stat().st_size for p in left) / 1e6,
            "t_scan": scan,
            "t_store": store,
            "t_render": render,
            "ratio_scan_to_render": scan / render,
            "ratio_store_to_render": store / render,
        }
    finally:
        shutil.rmtree(folder, ignore_errors=True)
        if old is None:
            os.environ.pop(urdf_cache.CACHE_ENV, None)
        else:
            os.environ[urdf_cache.CACHE_ENV] = old
    print(f"URDF cache at its cap ({result['entries']} entries, {result['megabytes']:.1f} MB):")
    print(f"  eviction scan          : {scan * 1e3:7.2f} ms")
    print(f"  store (write + scan)   : {store * 1e3:7.2f} ms")
    print(f"  xacro rendering        : {render * 1e3:7.2f} ms")
    print(f"  ratio scan / rendering : {result['ratio_scan_to_render']:7.3f}")
    return result


def main() -> None:
    """Print the figures (and, with ``--json``, one JSON object of them on the last line)."""
    args = parse_args(__doc__.splitlines()[0])
    emit(args, bench_urdf_cache())


if __name__ == "__main__":
    main()
