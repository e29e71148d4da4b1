"""Names resolved on first use, so that importing a package stays light.

Optional packages (the extras of ``pip install 'orthoglide-pin[...]'``) are
imported through :func:`optional_import`, which says in one line which extra
to install when one is missing.

A package whose modules import Pinocchio (or another heavy library) lists
those names with the module that defines them; :func:`lazy_exports` gives the
package its module-level ``__getattr__`` and ``__dir__`` (PEP 562), and the
module is imported only when one of its names is first asked for.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from types import ModuleType
from typing import Any, Final

from orthoglide_pin.exceptions import MissingExtraError

#: The extras of ``orthoglide-pin`` (pyproject.toml) and the modules each brings.
EXTRAS: Final = {
    "tables": ("pandas", "pyarrow"),
    "cluster": ("dask", "distributed"),
    "fea": ("Pynite",),
    "modal": ("openseespy",),
    "plan": ("toppra",),
    "sim": ("mujoco",),
}


def lazy_exports(
    package: str, names: Mapping[str, str], namespace: Mapping[str, Any]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """Module ``__getattr__`` and ``__dir__`` for names loaded on first use.

    Args:
        package: The package's ``__name__`` (for the error message).
        names: Exported name -> dotted name of the module that defines it.
        namespace: The package's ``globals()`` (listed by ``__dir__``).

    Returns:
        ``(__getattr__, __dir__)`` to assign at the package's top level.
    """

    def getattr_(name: str) -> Any:
        if name in names:
            return getattr(importlib.import_module(names[name]), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def dir_() -> list[str]:
        return sorted(set(namespace) | set(names))

    return getattr_, dir_


def optional_import(module: str, extra: str, feature: str = "this") -> ModuleType:
    """Import an optional package, or say which extra installs it.

    Args:
        module: The module, e.g. ``"pandas"``.
        extra: The extra of ``orthoglide-pin`` that brings it (:data:`EXTRAS`).
        feature: What needs it, for the message (``"orthoglide sweep"``).

    Returns:
        The module.

    Raises:
        MissingExtraError: One line: the package is missing and
            ``pip install 'orthoglide-pin[EXTRA]'`` installs it.
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtraError(module, extra, feature) from None
