"""Names resolved on first use, so that importing a package stays light.

A package whose modules import Pinocchio (or another heavy library) lists
those names with the module that defines them; :func:`lazy_exports` gives the
package its module-level ``__getattr__`` and ``__dir__`` (PEP 562), and the
module is imported only when one of its names is first asked for.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


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
