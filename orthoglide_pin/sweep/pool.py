"""Local execution of a sweep: this process first, worker processes when they pay.

:func:`run_local` evaluates the chunks of a sweep in this process and, when the
work left is worth it, on worker processes started in the background. The
rule, chosen from measurements on two cores (``benchmarks/bench_sweep.py``):

* **This process always works.** It takes chunks from the end of the queue;
  the workers take them from the front. The start-up of a worker (a fresh
  interpreter importing numpy and Pinocchio, ~0.5-1 s) therefore runs on
  another core while this process makes progress: it is hidden, not paid.
* **Default** (``workers=None``): the sweep starts in this process alone,
  one design at a time. After :data:`PROBE_CHUNKS` designs, the faster one
  (the first carries the imports and caches) estimates the work left; past
  :data:`POOL_AFTER` CPU seconds, ``cpus - 1`` workers start (:func:`cpu_count`),
  so the parent and the workers fill the CPUs. A small sweep never starts a
  process: it runs exactly as serially.
* ``workers=1``: this process only. ``workers=N``: ``N - 1`` workers start at
  once, with this process as the N-th.

Workers are started with ``spawn`` (no inherited threads or locks), with one
BLAS thread each (:data:`WORKER_ENVIRONMENT`), and never
outlive this process: each one ignores Ctrl-C (the parent decides, and stops
them), asks the kernel for ``SIGKILL`` when its parent dies (Linux
``PR_SET_PDEATHSIG``) and runs a watchdog thread that exits as soon as its
parent changes, so an interrupted, terminated or killed sweep leaves no
process behind. The parent terminates them once every chunk is in, or on any
error or interruption.

The end of a sweep never waits for a slow worker: with the queue empty, this
process takes on the chunks still out (the first result of a chunk is kept).
A worker that dies (killed, out of memory) loses nothing: its chunks go back to
the queue and this process finishes the sweep alone.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import ctypes
import ctypes.util
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Final

#: CPU seconds of estimated work left above which the default starts workers
#: (a worker's start costs about 1 s of CPU: a fresh interpreter, its imports).
#: CPU time, not wall time: on a busy machine the wall time of a design grows,
#: not the work a worker could take over.
POOL_AFTER: Final[float] = 3.0
#: Designs this process evaluates, one by one, before the default decides (the
#: first one carries the imports and caches, so the faster of the two is the estimate).
PROBE_CHUNKS: Final[int] = 2
#: Chunks queued per worker (one running, one waiting).
AHEAD: Final[int] = 2
#: Environment of the workers: one BLAS/OpenMP thread each (the sweep is parallel
#: over designs; threads of several processes spinning on two cores slow all down).
WORKER_ENVIRONMENT: Final = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
}
#: Seconds between two checks of a worker's watchdog.
WATCH_INTERVAL: Final[float] = 0.2
_PR_SET_PDEATHSIG: Final = 1
#: Signals held while workers start (see :func:`_spawning`).
_HELD: Final = frozenset({signal.SIGINT, signal.SIGTERM})
#: Seconds a worker gets to end after SIGTERM before SIGKILL.
TERMINATE_GRACE: Final[float] = 2.0

Rows = list[dict[str, Any]]
Chunk = Sequence[Mapping[str, Any]]
Task = Callable[[Chunk], Rows]


def cpu_count() -> int:
    """CPUs this process may run on (its affinity mask where the OS has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - macOS, Windows
        return max(1, os.cpu_count() or 1)


def _die_with_parent() -> None:  # pragma: no cover - Linux only, in the workers
    """Ask the kernel for ``SIGKILL`` when the parent dies (Linux; no-op elsewhere)."""
    if not sys.platform.startswith("linux"):
        return
    with contextlib.suppress(OSError, AttributeError):
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)


def _watch(parent: int) -> None:  # pragma: no cover - runs in the workers
    """Exit the worker at once when its parent process is gone."""
    while True:
        time.sleep(WATCH_INTERVAL)
        if os.getppid() != parent:
            os._exit(1)


def worker_init(parent: int) -> None:  # pragma: no cover - runs in the workers
    """Initialise a worker of :func:`run_local`: tie its life to the parent ``parent``.

    Args:
        parent: Process id of the sweep that started the worker.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a Ctrl-C pending since birth is dropped
    if hasattr(signal, "pthread_sigmask"):  # a SIGTERM pending since birth ends it here
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)
    _die_with_parent()
    if os.getppid() != parent:  # the parent died before the kernel was asked
        os._exit(1)
    threading.Thread(target=_watch, args=(parent,), name="parent-watchdog", daemon=True).start()


@contextlib.contextmanager
def _spawning(values: Mapping[str, str]) -> Iterator[None]:
    """Start processes inside with environment ``values``, SIGINT and SIGTERM held.

    A signal that arrives while a worker is being started is held until the
    start is complete (a worker cut off halfway through reading its start-up
    data prints a traceback), then delivered to the handler it was meant for.
    A worker inherits the blocked signals through ``exec``, so a Ctrl-C cannot
    interrupt its imports either: :func:`worker_init` drops it, and lets a
    pending SIGTERM end the worker.
    """
    old = {k: os.environ.get(k) for k in values}
    os.environ.update(values)
    main = threading.current_thread() is threading.main_thread()
    held: list[int] = []
    handlers = {s: signal.getsignal(s) for s in _HELD} if main else {}
    handlers = {s: h for s, h in handlers.items() if h is not None}  # None: not ours to swap
    for s in handlers:  # Python runs handlers in the main thread, whichever thread got it
        signal.signal(s, lambda signum, _frame: held.append(signum))
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)  # inherited by the workers
    try:
        yield
    finally:
        if hasattr(signal, "pthread_sigmask"):
            signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)
        for key, value in old.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
        for s, handler in handlers.items():
            signal.signal(s, handler)
        for signum in dict.fromkeys(held):
            signal.raise_signal(signum)  # now, to the handler it was meant for


class LocalWorkers:
    """Worker processes, started on demand, stopped for good on :meth:`close`.

    Args:
        count: Number of worker processes (>= 1).
    """

    def __init__(self, count: int) -> None:
        self.count = count
        self.pool: cf.ProcessPoolExecutor | None = None

    def start(self) -> cf.ProcessPoolExecutor:
        """Start the pool (its processes start with the first tasks)."""
        if self.pool is None:
            self.pool = cf.ProcessPoolExecutor(
                self.count,
                mp_context=multiprocessing.get_context("spawn"),
                initializer=worker_init,
                initargs=(os.getpid(),),
            )
        return self.pool

    def pool_broken(self) -> bool:
        """Whether a worker died and took the pool down with it."""
        return bool(getattr(self.pool, "_broken", False))

    def close(self) -> None:
        """Stop the workers at once (whatever they are doing) and reap them."""
        pool, self.pool = self.pool, None
        if pool is None:
            return
        processes = list((getattr(pool, "_processes", None) or {}).values())
        pool.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            with contextlib.suppress(Exception):
                process.terminate()
        for process in processes:
            with contextlib.suppress(Exception):
                process.join(timeout=TERMINATE_GRACE)
                if process.is_alive():  # still starting, its SIGTERM held: no grace
                    process.kill()
                    process.join(timeout=TERMINATE_GRACE)


def run_local(
    task: Task, chunks: Sequence[Chunk], workers: int | None, *, cpus: int | None = None
) -> Iterator[Rows]:
    """Evaluate ``chunks`` here and on local workers; yield each chunk's rows when done.

    Once the queue is empty, this process takes on the chunks still out with
    the workers (the newest first) instead of waiting for them: a slow worker
    never makes the sweep wait, and the first result of a chunk is the one kept
    (every evaluation of a chunk gives the same rows).

    Args:
        task: The function of one chunk (top-level, picklable).
        chunks: The chunks, in order (the workers take the front, this process the end).
        workers: ``None`` for the default rule, else the processes that work,
            this one included (see the module).
        cpus: CPUs of the default rule (default: :func:`cpu_count`).

    Yields:
        The rows of each chunk, once, in the order they finish.
    """
    auto = workers is None
    extra = (cpus or cpu_count()) - 1 if workers is None else workers - 1
    local = LocalWorkers(max(extra, 1))
    pending: deque[tuple[int, Chunk]] = deque(enumerate(chunks))
    made = len(pending)  # ids of the chunks; a probe's split gets new ones
    out: dict[cf.Future[Rows], tuple[int, Chunk]] = {}
    done: set[int] = set()
    per_design: list[float] = []
    try:
        if not auto and extra > 0:
            local.start()
        while pending or out:
            if auto and extra > 0 and local.pool is None and len(per_design) >= PROBE_CHUNKS:
                left = sum(len(c) for _, c in pending)
                if left * min(per_design) > POOL_AFTER:
                    local.start()
            pool = local.pool
            if pool is not None and pending and len(out) < AHEAD * local.count:
                with _spawning(WORKER_ENVIRONMENT):  # the processes start on submit
                    while pending and len(out) < AHEAD * local.count:
                        item = pending.popleft()
                        out[pool.submit(task, item[1])] = item
            finished = [f for f in out if f.done()]
            for future in finished:
                key, chunk = out.pop(future)
                if key in done:  # this process did it first
                    continue
                try:
                    rows = future.result()
                except BrokenProcessPool:  # a worker died (killed, out of memory)
                    pending.append((key, chunk))
                    continue
                done.add(key)
                yield rows
            if local.pool is not None and local.pool_broken():
                # Carry on here: what was out goes back to the queue.
                pending.extend(item for item in out.values() if item[0] not in done)
                out.clear()
                local.close()
                extra = 0  # never started again
            if pending:
                key, chunk = pending.pop()
                if auto and local.pool is None and len(chunk) > 1:
                    pending.append((made, chunk[:-1]))  # probe one design at a time
                    made, chunk = made + 1, chunk[-1:]
            else:
                left_out = [item for item in out.values() if item[0] not in done]
                if not left_out:
                    break  # every chunk is done
                key, chunk = max(left_out, key=lambda item: item[0])
            start = time.process_time()  # CPU seconds: what a worker would take over
            rows = task(chunk)
            per_design.append((time.process_time() - start) / max(len(chunk), 1))
            if key not in done:
                done.add(key)
                yield rows
    finally:
        for future in out:
            future.cancel()
        # Every result is in (or the sweep failed): a worker still busy only
        # repeats a chunk done here, so the workers are stopped, not awaited.
        local.close()


__all__ = ["POOL_AFTER", "LocalWorkers", "cpu_count", "run_local", "worker_init"]
