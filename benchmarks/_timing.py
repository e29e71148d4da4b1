"""Timing helpers shared by the benchmarks: best-of-N wall times [s]."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
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
