"""The notebooks run quietly: kernels on IPC sockets, not TCP, and no INFO lines.

myst-nb executes every notebook on a kernel that jupyter_client starts with
its defaults: TCP sockets on localhost, unencrypted, about which each kernel
prints a warning. The build has no use for a network port: like the test suite
(``tests/_notebooks.py``), it gives the kernels IPC sockets in a folder of the
build's own, removed when the build ends, so the kernel opens no port and
has nothing to warn about. myst-nb takes no options for the kernel manager, so
the defaults of jupyter_client's kernel managers are set for this process.

A Pygments plugin (accessible-pygments, whose styles Pygments loads while the
theme looks its style up) calls ``logging.basicConfig(level=INFO)`` when it is
imported, so every library's INFO message (nbclient's "Executing notebook with
kernel" for each notebook) would print; :func:`quiet_root_logger` gives the
root logger Python's default level back. Warnings still print.
"""

from __future__ import annotations

import atexit
import logging
import shutil
import tempfile
from pathlib import Path
from typing import Any


def ipc_kernels(app: Any) -> None:
    """Make every kernel manager of this process use IPC sockets in a private folder."""
    from jupyter_client.connect import ConnectionFileMixin
    from jupyter_client.manager import AsyncKernelManager, KernelManager

    folder = Path(tempfile.mkdtemp(prefix="orthoglide-docs-kernels-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    ConnectionFileMixin.class_traits()["transport"].default_value = "ipc"

    def socket_path(manager: Any) -> str:
        return str(folder / "kernel")

    # The socket path must be absolute: the kernel runs in another folder.
    for cls in (KernelManager, AsyncKernelManager):
        cls._all_trait_default_generators["ip"] = socket_path


def quiet_root_logger(app: Any) -> None:
    """Python's default level (WARNING) for the root logger, if an import lowered it."""
    root = logging.getLogger()
    if root.level < logging.WARNING:
        root.setLevel(logging.WARNING)
