"""Timing helpers shared by the benchmarks: best-of-N wall times [s], JSON output."""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any


def best_per_call(fn: Callable[[], object], calls: int, repeats: int = 5) -> float:
    """Best time per call [s] over ``repeats`` runs of ``calls`` calls of ``fn``."""
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - start) / calls)
    return best


def best_times(fns: list[Callable[[], Any]], repeats: int) -> list[float]:
    """Best wall time [s] of each function, timed in turn (interleaved) after a warm-up.

    Interleaving keeps the ratios meaningful on a shared, noisy machine.
    """
    for fn in fns:
        fn()
    best = [math.inf] * len(fns)
    for _ in range(repeats):
        for i, fn in enumerate(fns):
            start = time.perf_counter()
            fn()
            best[i] = min(best[i], time.perf_counter() - start)
    return best


def _plain(value: Any) -> Any:
    """``value`` with numpy scalars and arrays as Python numbers and lists; non-finite: None."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return _plain(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def parse_args(description: str, argv: Sequence[str] | None = None) -> argparse.Namespace:
    """The benchmarks' common options: ``--json``."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument(
        "--json",
        action="store_true",
        help="after the table, print one JSON object of the figures on the last line",
    )
    return parser.parse_args(argv)


def emit(args: argparse.Namespace, figures: Mapping[str, Any]) -> None:
    """Print ``figures`` as one strict JSON object on one line when ``--json`` was given."""
    if args.json:
        sys.stdout.flush()
        print(json.dumps(_plain(figures), allow_nan=False, sort_keys=True), flush=True)
