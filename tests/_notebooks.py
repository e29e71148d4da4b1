"""The notebooks, executed once per test run, headless, on a kernel of this environment.

Each notebook is executed by nbclient on a fresh ipykernel registered from the
running interpreter, over IPC sockets (no notebook server, no network port),
in an empty working directory of its own. The notebook tests check the
executed copies, and the documentation tests build the site from them, so
that no notebook runs twice.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

NOTEBOOKS = Path(__file__).resolve().parents[1] / "notebooks"
#: Seconds allowed for one cell (the whole notebook takes well under this).
CELL_TIMEOUT = 120
KERNEL = "orthoglide-pin-tests"


@dataclass
class Executed:
    """One executed notebook: its cells with their outputs, and what it left behind."""

    name: str
    book: Any
    left_behind: list[str]


@contextmanager
def kernel_spec(prefix: Path) -> Iterator[str]:
    """A kernel spec for this interpreter under ``prefix``, found through ``JUPYTER_PATH``."""
    from ipykernel import kernelspec

    kernelspec.install(kernel_name=KERNEL, prefix=str(prefix))
    spec = prefix / "share" / "jupyter" / "kernels" / KERNEL / "kernel.json"
    assert sys.executable in spec.read_text()
    old = os.environ.get("JUPYTER_PATH")
    os.environ["JUPYTER_PATH"] = str(prefix / "share" / "jupyter")
    try:
        yield KERNEL
    finally:
        if old is None:
            os.environ.pop("JUPYTER_PATH", None)
        else:
            os.environ["JUPYTER_PATH"] = old


class NotebookRuns:
    """Executes each notebook on first request and keeps the result for the session."""

    def __init__(self, kernel: str, scratch: Any) -> None:
        self._kernel = kernel
        self._scratch = scratch  # pytest's tmp_path_factory
        self._done: dict[str, Executed] = {}

    def names(self) -> list[str]:
        """The notebooks of ``notebooks/``, sorted."""
        return sorted(p.name for p in NOTEBOOKS.glob("*.ipynb"))

    def get(self, name: str) -> Executed:
        """Notebook ``name``, executed (once)."""
        if name not in self._done:
            workdir = self._scratch.mktemp(f"run-{Path(name).stem}")
            sockets = self._scratch.mktemp("ipc")
            self._done[name] = execute(name, self._kernel, workdir, sockets)
        return self._done[name]


def execute(name: str, kernel: str, workdir: Path, sockets: Path) -> Executed:
    """Run notebook ``name`` top to bottom in ``workdir``; raise on the first failing cell."""
    import jupyter_client
    import nbclient
    import nbformat

    book = nbformat.read(NOTEBOOKS / name, as_version=4)
    # IPC sockets in a folder of their own: the kernel opens no network port.
    manager = jupyter_client.AsyncKernelManager(
        kernel_name=kernel, transport="ipc", ip=str(sockets / "kernel")
    )
    client = nbclient.NotebookClient(
        book,
        km=manager,
        kernel_name=kernel,
        timeout=CELL_TIMEOUT,
        resources={"metadata": {"path": str(workdir)}},
    )
    # raises CellExecutionError on the first failing cell; either way the kernel is
    # shut down (nbclient keeps a kernel alive whose manager it was given)
    client.execute(cleanup_kc=True)
    return Executed(name, book, sorted(p.name for p in workdir.iterdir()))
