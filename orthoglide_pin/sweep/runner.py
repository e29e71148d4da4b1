"""Running a sweep: chunks of designs on worker processes, a Dask cluster or any executor.

:func:`run_sweep` evaluates every design of a :class:`~orthoglide_pin.sweep.spec.SweepSpec`
and writes, under its output directory ``DIR``:

* ``DIR/sweep.json``: the sweep's description;
* ``DIR/parts/<key>.json``: one row per finished design, each written
  atomically as soon as its chunk comes back (a reader, or a rerun, never sees
  a half-written part);
* ``DIR/results.csv`` and ``DIR/results.parquet``: the tidy table
  (:func:`~orthoglide_pin.sweep.table.sweep_table`), assembled from the parts in the
  grid's order, written atomically at the end of every run.

Nothing is lost: a rerun skips the designs whose part is complete, so a sweep
killed midway and started again gives the same table as an uninterrupted run
(the table is always assembled from the parts, whatever ran them); a damaged
part is computed again. The directory must be new, empty, the package's own
(its marker) or an earlier sweep's with the same spec, else it is refused
before anything is written (:mod:`~orthoglide_pin.sweep.store`).

Execution, in order of precedence:

* ``executor``: any :class:`concurrent.futures.Executor` (the caller owns it);
* ``scheduler``: a Dask distributed cluster, ``"tcp://HOST:PORT"``, or
  ``"local"`` for a :class:`distributed.LocalCluster` of ``workers`` processes on
  127.0.0.1 without dashboard, or a ``distributed.Client`` (Dask is imported
  only then); a worker lost midway has its tasks run again elsewhere;
* otherwise this process, joined by local worker processes when the sweep is
  large enough to gain from them (:mod:`orthoglide_pin.sweep.pool`: the rule,
  and why the default is never slower than a serial run); ``workers=1`` runs
  in this process only.

Sizes are checked before anything is allocated or started: at most
:data:`MAX_DESIGNS` designs (``force_designs`` allows up to
:data:`~orthoglide_pin.sweep.spec.HARD_MAX_DESIGNS`), at most one local worker
per CPU (``force_workers`` allows more, up to :data:`MAX_WORKERS`); the grids
are capped by :class:`~orthoglide_pin.sweep.spec.SweepSpec`.

Designs go out in chunks (``chunk_size``; by default about four chunks per
worker, at most :data:`MAX_CHUNK` designs each), so the per-task overhead of a
process pool (~1 ms) or Dask (~2 ms) stays small against the ~25-150 ms of a
design, and a killed sweep loses at most the chunks in flight. A progress bar
(tqdm, on standard error, shown on a terminal only) counts the designs.
"""

from __future__ import annotations

import concurrent.futures as cf
import io
import math
from collections.abc import Callable, Generator, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from orthoglide_pin._io import atomic_write_bytes, atomic_write_text, json_text
from orthoglide_pin._lazy import optional_import
from orthoglide_pin._outdir import claim_directory
from orthoglide_pin._paths import given_path
from orthoglide_pin._validation import flag, instance_of, optional_callable, path_argument
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.sweep.metrics import evaluate_designs
from orthoglide_pin.sweep.pool import cpu_count, run_local
from orthoglide_pin.sweep.scheduler import check_scheduler
from orthoglide_pin.sweep.spec import HARD_MAX_DESIGNS, SweepSpec, design_key
from orthoglide_pin.sweep.store import (
    OWN_NAMES,
    PARTS,
    SPEC_NAME,
    check_spec,
    is_earlier_sweep,
    load_parts,
    write_part,
)
from orthoglide_pin.sweep.table import sweep_table

if TYPE_CHECKING:
    import pandas as pd

#: Most designs in one task.
MAX_CHUNK: Final[int] = 4
#: Chunks per worker when the chunk size is not given.
CHUNKS_PER_WORKER: Final[int] = 4
#: Most designs in one sweep unless forced (about 4 to 20 minutes per 10,000
#: designs and CPU at the default grids; larger sweeps belong on a cluster).
MAX_DESIGNS: Final[int] = 10_000
#: Most local worker processes, even when forced.
MAX_WORKERS: Final[int] = 256
#: Seconds to wait for a remote Dask scheduler.
CONNECT_TIMEOUT: Final[float] = 10.0
CSV_NAME: Final = "results.csv"
PARQUET_NAME: Final = "results.parquet"

Task = Callable[[Sequence[Mapping[str, Any]]], list[dict[str, Any]]]


@dataclass(frozen=True)
class SweepResult:
    """The outcome of :func:`run_sweep`.

    Attributes:
        table: The tidy table, one row per design, in grid order.
        out: The output directory.
        csv: Path of the CSV table.
        parquet: Path of the Parquet table.
        designs: Number of designs in the sweep.
        computed: Designs evaluated by this run.
        skipped: Designs found done (their part existed).
        invalid: Designs whose status is ``"invalid"``.
    """

    table: pd.DataFrame
    out: Path
    csv: Path
    parquet: Path
    designs: int
    computed: int
    skipped: int
    invalid: int

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (paths as text)."""
        return {
            "out": str(self.out),
            "csv": str(self.csv),
            "parquet": str(self.parquet),
            "designs": self.designs,
            "computed": self.computed,
            "skipped": self.skipped,
            "invalid": self.invalid,
        }


def assemble(out: str | Path, spec: SweepSpec) -> pd.DataFrame:
    """The table of the designs of ``spec`` done so far, in grid order."""
    designs = spec.designs()
    rows = load_parts(out, designs)
    keys = [design_key(d) for d in designs]
    return sweep_table(
        [rows[k] for k in keys if k in rows],
        spec.names,
        spec.program is not None,
        spec.cut is not None,
    )


def require_tables() -> None:
    """Check that the table stack (pandas, pyarrow) is installed, before any work.

    Raises:
        MissingExtraError: One line: ``pip install 'orthoglide-pin[tables]'``.
    """
    for module in ("pandas", "pyarrow"):
        optional_import(module, "tables", "a sweep (its results table)")


def write_tables(out: str | Path, table: pd.DataFrame) -> tuple[Path, Path]:
    """Write ``table`` as ``out/results.csv`` and ``out/results.parquet``, atomically."""
    folder = Path(out)
    csv, parquet = folder / CSV_NAME, folder / PARQUET_NAME
    atomic_write_text(csv, table.to_csv(index=False))
    buf = io.BytesIO()
    table.to_parquet(buf, index=False)
    atomic_write_bytes(parquet, buf.getvalue())
    return csv, parquet


def _chunks(items: Sequence[Any], size: int) -> list[list[Any]]:
    return [list(items[i : i + size]) for i in range(0, len(items), size)]


def _positive(name: str, value: int | None) -> int | None:
    if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
        raise InvalidParameterError(name, value, "a positive integer")
    return value


@contextmanager
def _dask(scheduler: Any, workers: int | None) -> Iterator[tuple[cf.Executor, int]]:
    """A Dask executor and its worker count; closes what it opened."""
    distributed: Any = optional_import("distributed", "cluster", "a Dask scheduler")
    Client, LocalCluster = distributed.Client, distributed.LocalCluster
    opened: list[Any] = []
    try:
        if isinstance(scheduler, Client):
            client = scheduler
        elif scheduler == "local":
            cluster = LocalCluster(
                n_workers=workers or cpu_count(),
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                # no dashboard, and the scheduler's HTTP endpoint on a free port of
                # 127.0.0.1 (its default, 8787, may be taken: another sweep, a cluster)
                dashboard_address="127.0.0.1:0",
                scheduler_kwargs={"dashboard": False},
                silence_logs=40,  # logging.ERROR
            )
            opened.append(cluster)
            client = Client(cluster)
            opened.append(client)
        elif isinstance(scheduler, str) and scheduler.startswith("tcp://"):
            try:
                client = Client(scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError) as exc:
                raise InvalidParameterError(
                    "scheduler", scheduler, f"a reachable Dask scheduler ({exc})"
                ) from None
            opened.append(client)
        else:
            raise InvalidParameterError(
                "scheduler", scheduler, "'local', tcp://HOST:PORT or a distributed.Client"
            )
        threads = sum(client.nthreads().values()) or 1
        yield client.get_executor(pure=False), threads
    finally:
        for thing in reversed(opened):
            thing.close()


@contextmanager
def _remote(
    executor: cf.Executor | None, scheduler: Any, workers: int | None
) -> Iterator[tuple[cf.Executor, int]]:
    """The caller's executor or a Dask one, and its number of workers."""
    if executor is not None:
        yield executor, workers or getattr(executor, "_max_workers", None) or 1
    else:
        with _dask(scheduler, workers) as pair:
            yield pair


def check_sizes(
    spec: SweepSpec,
    workers: int | None,
    *,
    force_workers: bool = False,
    force_designs: bool = False,
) -> None:
    """Refuse a sweep too large or too many local workers (before anything is made).

    Raises:
        InvalidParameterError: More than :data:`MAX_DESIGNS` designs without
            ``force_designs``; more workers than CPUs without ``force_workers``
            (never more than :data:`MAX_WORKERS`).
    """
    _positive("workers", workers)
    n = len(spec)  # the product of the axes' lengths: nothing is built yet
    if n > MAX_DESIGNS and not force_designs:
        raise InvalidParameterError(
            "number of designs",
            n,
            f"at most {MAX_DESIGNS} designs in one sweep (a design takes ~0.03-0.15 s "
            "of one CPU at the default grids); split the sweep or force it (--force-designs)",
        )
    if n > HARD_MAX_DESIGNS:  # pragma: no cover - SweepSpec refuses it first
        raise InvalidParameterError("designs", n, f"at most {HARD_MAX_DESIGNS} designs")
    cpus = cpu_count()
    if workers is not None and workers > cpus and not force_workers:
        raise InvalidParameterError(
            "workers", workers, f"at most {cpus}, the CPUs of this machine (--force-workers)"
        )
    if workers is not None and workers > MAX_WORKERS:
        raise InvalidParameterError("workers", workers, f"at most {MAX_WORKERS}")


def _progress(total: int, done: int, enabled: bool) -> Any:
    from tqdm import tqdm

    return tqdm(
        total=total, initial=done, unit="design", desc="sweep", disable=None if enabled else True
    )


_FLAGS: Final = ("progress", "force_workers", "force_designs", "force")


def _check_arguments(spec: Any, out: Any, executor: Any, scheduler: Any, task: Any) -> None:
    """Refuse arguments of :func:`run_sweep` of the wrong kind, naming them."""
    instance_of("spec", spec, SweepSpec, "a SweepSpec")
    path_argument("out", out)
    if executor is not None:
        instance_of("executor", executor, cf.Executor, "a concurrent.futures.Executor or None")
    if not (scheduler is None or isinstance(scheduler, str) or hasattr(scheduler, "submit")):
        allowed = "'local', tcp://HOST:PORT, a distributed.Client or None"
        raise InvalidParameterError("scheduler", scheduler, allowed)
    if optional_callable("task", task, "a top-level function of a chunk of designs") is None:
        raise InvalidParameterError("task", task, "a top-level function of a chunk of designs")


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    *,
    executor: cf.Executor | None = None,
    scheduler: Any = None,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: bool = True,
    task: Task = evaluate_designs,
    force_workers: bool = False,
    force_designs: bool = False,
    force: bool = False,
) -> SweepResult:
    """Evaluate every design of ``spec`` not done yet under ``out`` (see the module).

    Args:
        spec: The sweep.
        out: Output directory (created if needed).
        executor: Any ``concurrent.futures.Executor`` to run the chunks on.
        scheduler: Dask: ``"local"``, ``"tcp://HOST:PORT"`` or a ``distributed.Client``.
        workers: Processes that evaluate designs, this one included (default:
            this one, joined by one worker per other CPU when the sweep is
            large, see :mod:`~orthoglide_pin.sweep.pool`; 1: this process only),
            or the workers of ``scheduler="local"``.
        chunk_size: Designs per task (default: see the module).
        progress: Show the progress bar (on a terminal).
        task: The function run on each chunk (top-level, picklable).
        force_workers: Allow more local workers than CPUs.
        force_designs: Allow more than :data:`MAX_DESIGNS` designs.
        force: Also write into a non-empty directory that holds no sweep
            (its other files are kept).

    Returns:
        The table and counts; the table is also in ``out/results.{csv,parquet}``.

    Raises:
        InvalidParameterError: Bad ``workers``, ``chunk_size`` or ``scheduler``
            (an address is probed first, even when no work is left: see
            :mod:`~orthoglide_pin.sweep.scheduler`), or a sweep over its caps
            (see :func:`check_sizes`).
        OutputPathError: ``out`` is a non-empty directory that holds no
            earlier sweep (unless ``force``), or an earlier sweep with another
            spec, or cannot be written (:mod:`~orthoglide_pin.sweep.store`);
            checked before anything is written.
        MissingExtraError: pandas or pyarrow (``[tables]``) is not installed, or
            Dask (``[cluster]``) for a ``scheduler``; checked before any work.
    """
    require_tables()
    _check_arguments(spec, out, executor, scheduler, task)
    given = (progress, force_workers, force_designs, force)
    progress, force_workers, force_designs, force = (
        flag(n, v) for n, v in zip(_FLAGS, given, strict=True)
    )
    if scheduler is not None and executor is None:
        optional_import("distributed", "cluster", "a Dask scheduler")
    check_sizes(spec, workers, force_workers=force_workers, force_designs=force_designs)
    _positive("chunk_size", chunk_size)
    if executor is None:
        check_scheduler(scheduler)  # even with no work left: a bad address is never silent
    folder = given_path(out, 'a directory ("." is the current one)')
    check_spec(folder, spec)
    claim_directory(folder, OWN_NAMES, force=force, earlier=is_earlier_sweep, folders={PARTS})
    (folder / PARTS).mkdir(parents=True, exist_ok=True)
    atomic_write_text(folder / SPEC_NAME, json_text(spec.to_dict(), indent=1) + "\n")
    designs = spec.designs()
    keys = [design_key(d) for d in designs]
    done = load_parts(folder, designs)
    todo = [d for d, k in zip(designs, keys, strict=True) if k not in done]
    computed = 0
    if todo:
        bar = _progress(len(designs), len(designs) - len(todo), progress)
        results = _results(todo, task, executor, scheduler, workers, chunk_size)
        try:
            for rows in results:
                for row in rows:
                    write_part(folder, row)
                computed += len(rows)
                bar.update(len(rows))
        finally:
            results.close()  # stops the workers at once after an error or an interruption
            bar.close()
    table = assemble(folder, spec)
    csv, parquet = write_tables(folder, table)
    invalid = int((table["status"] == "invalid").sum())
    skipped = len(designs) - len(todo)
    return SweepResult(table, folder, csv, parquet, len(designs), computed, skipped, invalid)


def _size(todo: int, workers: int, chunk_size: int | None) -> int:
    return chunk_size or max(1, min(MAX_CHUNK, math.ceil(todo / (CHUNKS_PER_WORKER * workers))))


def _results(
    todo: Sequence[dict[str, Any]],
    task: Task,
    executor: cf.Executor | None,
    scheduler: Any,
    workers: int | None,
    chunk_size: int | None,
) -> Generator[list[dict[str, Any]], None, None]:
    """The rows of every chunk of ``todo``, in the order they finish."""
    if executor is None and scheduler is None:
        n = workers or cpu_count()
        yield from run_local(task, _chunks(todo, _size(len(todo), n, chunk_size)), workers)
        return
    with _remote(executor, scheduler, workers) as (pool, n):
        futures = [pool.submit(task, c) for c in _chunks(todo, _size(len(todo), n, chunk_size))]
        try:
            for future in cf.as_completed(futures):
                yield future.result()
        finally:
            for future in futures:  # after an error: what has not started never will
                future.cancel()


__all__ = [
    "CSV_NAME",
    "MAX_DESIGNS",
    "PARQUET_NAME",
    "SweepResult",
    "assemble",
    "check_sizes",
    "load_parts",
    "run_sweep",
    "write_part",
    "write_tables",
]
