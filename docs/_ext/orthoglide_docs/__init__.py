"""Sphinx extension: the reference pages of orthoglide-pin, generated from the package.

* **API pages** (``api/``): one page per layer, written when the build starts,
  with an entry for every name of ``orthoglide_pin.__all__``. A name belongs to
  the layer whose ``__all__`` holds it; the errors of
  ``orthoglide_pin.exceptions`` get their own page, and ``__version__`` sits on
  the index. A new layer gets its page without any change here (its place
  comes from ``orthoglide_api_order`` in ``conf.py``, else alphabetical). A
  public name without a docstring of its own is a warning, so a strict build
  fails on it.
* **Command-line reference** (the ``orthoglide-cli`` directive): every command
  of :func:`orthoglide_pin.cli.build_parser`, its usage and every option and
  argument with the help text that ``--help`` prints (defaults included), as
  ``program``/``option`` entries that pages can link to.
* **References**: a cross-reference to an object that exists but has no page
  (numpy, Pinocchio, the standard library, a private helper of the package)
  renders as code; a reference to a module path of a public name goes to its
  public entry (``orthoglide_pin.machine.params.OrthoglideParams`` to
  ``orthoglide_pin.OrthoglideParams``). A reference to nothing that exists stays
  a warning.
* **Kernels**: the notebooks run on kernels that talk to the build over IPC
  sockets, not TCP, and print nothing (``orthoglide_docs.kernel``).
"""

from __future__ import annotations

from typing import Any

from sphinx.application import Sphinx

from orthoglide_docs.api import api_groups, own_doc, write_api_pages
from orthoglide_docs.cli import EVERY_COMMAND, CliReference
from orthoglide_docs.fields import FieldsTable
from orthoglide_docs.kernel import ipc_kernels, quiet_root_logger
from orthoglide_docs.references import fix_signature, no_inline_type, resolve_missing

__all__ = ["EVERY_COMMAND", "api_groups", "own_doc", "setup"]


def setup(app: Sphinx) -> dict[str, Any]:
    """Register the generated pages, the directive and the reference resolver."""
    app.add_config_value("orthoglide_api_order", [], "env")
    app.connect("builder-inited", write_api_pages)
    app.connect("builder-inited", ipc_kernels)
    app.connect("builder-inited", quiet_root_logger)
    app.connect("missing-reference", resolve_missing)
    app.connect("autodoc-process-signature", fix_signature)
    app.connect("autodoc-process-docstring", no_inline_type, priority=900)
    app.add_directive("orthoglide-cli", CliReference)
    app.add_directive("orthoglide-fields", FieldsTable)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
