"""numba, optional: whether it is installed, and how the package compiles a loop with it.

The package's compiled loops (TOPP-RA's passes, the blends' samples and
arc-length tables, the torque rows, the verification, the path forms, the
servo loop of ``simulate``) are plain Python functions over arrays and
numbers, compiled by numba on first use when numba is installed (the
``[plan]`` and ``[sim]`` extras); each keeps an array version that runs
without it and gives the same numbers (the tests compare the two). This
module is below every layer: :data:`AVAILABLE` says whether numba is there,
:func:`jit` compiles a function the one way the package does.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

numba: Any
try:  # numba is optional: the array versions run without it
    import numba
except ImportError:  # pragma: no cover - exercised where numba is missing
    numba = None

#: Whether the compiled loops can run (numba is installed).
AVAILABLE: Final[bool] = numba is not None


def jit(function: Callable[..., Any], *, inline: bool = False) -> Callable[..., Any]:
    """``function`` compiled by numba on first use; numba must be installed.

    The function is compiled without the interpreter's lock (``nogil``: a
    second thread runs while it does) and with numpy's error model (``x / 0``
    gives ``inf`` or ``nan``, as in numpy). The compiled code is cached on
    disk (beside the module, or in the user's cache folder); where neither can
    be written it is compiled in each process.

    Args:
        function: The function.
        inline: Compile it into its callers (a helper called in a loop, where
            a call passing arrays costs more than a few rows' arithmetic).
    """
    assert numba is not None
    options: dict[str, Any] = {"nogil": True, "error_model": "numpy"}
    if inline:
        options["inline"] = "always"
    try:
        return numba.njit(cache=True, **options)(function)  # type: ignore[no-any-return,unused-ignore]
    except RuntimeError:  # numba found no folder to cache in
        return numba.njit(**options)(function)  # type: ignore[no-any-return,unused-ignore]
