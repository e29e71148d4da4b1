"""How a command ends: signals, broken pipes and library warnings.

Every ``orthoglide`` command runs inside :func:`guarded`, which gives it the
behaviour of a well-mannered Unix tool:

* **Ctrl-C (SIGINT)** prints ``orthoglide: interrupted`` and exits with
  status 130; **SIGTERM** prints ``orthoglide: terminated`` and exits with
  status 143 (128 + the signal number, as a shell reports a process killed by
  it). The signal becomes an exception in the main thread, so every
  ``finally`` and every temporary-file cleanup of the package runs; further
  signals are ignored until the command has cleaned up (SIGKILL still works,
  and the temporary files it leaves are removed by the next run).
* **A closed pipe** (``orthoglide urdf | head``) ends the command quietly with
  status 141 (128 + SIGPIPE), with no traceback and no message.
* **Warnings** of numpy and other libraries never reach the terminal: what
  they meant (a NaN or an infinity in a result) is caught by the check of
  every output (:func:`orthoglide_pin.cli._common.emit`) and reported as the
  package's own error.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Callable, Iterator
from types import FrameType
from typing import Final

import numpy as np

#: Exit statuses: 128 + the signal number.
EXIT_INTERRUPTED: Final = 128 + signal.SIGINT
EXIT_TERMINATED: Final = 128 + signal.SIGTERM
EXIT_BROKEN_PIPE: Final = 128 + getattr(signal, "SIGPIPE", 13)  # 13 where it is not defined


class Terminated(BaseException):
    """SIGTERM, raised in the main thread like KeyboardInterrupt for SIGINT."""


#: Set once the first signal has been raised, until the outermost guard exits.
_FIRED: list[int] = []


def _raise_for(signum: int, _frame: FrameType | None) -> None:
    """Turn the first SIGINT or SIGTERM into an exception; ignore the next ones."""
    _FIRED.append(signum)
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, signal.SIG_IGN)  # the cleanup that follows runs undisturbed
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated


@contextlib.contextmanager
def signals_as_exceptions(*, force_sigint: bool = False) -> Iterator[None]:
    """SIGINT raises KeyboardInterrupt and SIGTERM raises :class:`Terminated`.

    The previous handlers are restored on exit. Outside the main thread this
    does nothing (Python delivers signals to the main thread only).

    Args:
        force_sigint: Also catch SIGINT where it was inherited as ignored (a
            background job); by default such a SIGINT stays ignored, as the
            shell meant.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    outermost = not any(old is _raise_for for old in previous.values())
    if outermost:
        _FIRED.clear()
    for s, old in previous.items():
        if not _FIRED and (s == signal.SIGTERM or old is not signal.SIG_IGN or force_sigint):
            signal.signal(s, _raise_for)
    try:
        yield
    finally:
        for s, old in previous.items():
            if _FIRED and not outermost:
                signal.signal(s, signal.SIG_IGN)  # still cleaning up after the first signal
            else:
                signal.signal(s, old if old is not None else signal.SIG_DFL)
        if outermost:
            _FIRED.clear()


def silence_stdout() -> None:
    """Point stdout at ``/dev/null`` after a broken pipe, so exiting flushes nowhere."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def say(message: str, *, new_line: bool = False) -> None:
    """Print one line ``orthoglide: MESSAGE`` on stderr (never fails).

    Args:
        message: The message.
        new_line: Start on a new line when stderr is a terminal (after the
            ``^C`` it echoes, or a progress bar).
    """
    with contextlib.suppress(OSError, ValueError, AttributeError):
        start = "\n" if new_line and sys.stderr.isatty() else ""
        print(f"{start}orthoglide: {message}", file=sys.stderr, flush=True)


@contextlib.contextmanager
def quiet_libraries() -> Iterator[None]:
    """No warning from numpy or another library reaches the terminal.

    Nor from the Python processes the command starts (a sweep's workers):
    they inherit ``PYTHONWARNINGS=ignore``. The previous filters and
    environment are restored on exit.
    """
    previous = os.environ.get("PYTHONWARNINGS")
    os.environ["PYTHONWARNINGS"] = "ignore"
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        if previous is None:
            os.environ.pop("PYTHONWARNINGS", None)
        else:
            os.environ["PYTHONWARNINGS"] = previous


def wait_for_signal(alive: Callable[[], bool] | None = None, poll: float = 0.25) -> None:
    """Block until SIGINT or SIGTERM (raised as exceptions), or ``alive()`` is false.

    Args:
        alive: A callable polled every ``poll`` seconds, or ``None`` to wait
            for a signal only.
        poll: Polling period [s].
    """
    import time

    with signals_as_exceptions(force_sigint=True):
        while alive is None or alive():
            time.sleep(poll)
