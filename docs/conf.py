"""Sphinx configuration of the orthoglide-pin documentation site.

Build it with ``make docs`` (strict: every warning is an error, every
cross-reference must resolve); the site lands in ``site/`` and opens as static
files, offline. The API reference (``api/``) and the command-line reference are
generated from the package itself by ``_ext/orthoglide_docs/``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import orthoglide_pin

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

project = "orthoglide-pin"
author = "the orthoglide-pin authors"
copyright = "the orthoglide-pin authors, BSD-3-Clause"
release = orthoglide_pin.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "myst_nb",
    "orthoglide_docs",
]

# ---------------------------------------------------------------- sources
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "notebooks/README.md"]
# Every reference must resolve; references to objects of numpy, Pinocchio and
# the like, or to the package's private helpers, render as plain code
# (orthoglide_docs resolves them; a name that exists nowhere still fails).
nitpicky = True

# ---------------------------------------------------------------- MyST
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3

# ---------------------------------------------------------------- notebooks
# Executed at build time, top to bottom; a failing cell fails the build. The
# test suite builds the site from the notebooks it has just executed instead
# (``-D nb_execution_mode=off``), so that they run once per test run.
nb_execution_mode = "force"
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_in_temp = True
nb_merge_streams = True

# ---------------------------------------------------------------- autodoc
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_typehints_format = "short"
autodoc_preserve_defaults = True
autodoc_type_aliases = {
    name: name for name in ("ArrayLike", "FloatArray", "IntArray", "BoolArray", "IndexArray")
}
python_use_unqualified_type_names = True
add_module_names = False
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_ivar = True
napoleon_use_rtype = False

# The API pages, one per layer, in the order of the architecture (a layer not
# listed comes after these, in alphabetical order).
orthoglide_api_order = [
    "machine",
    "kinematics",
    "kinetostatics",
    "calibration",
    "dynamics",
    "motion",
    "drives",
    "planning",
    "elasticity",
    "machining",
    "report",
    "simulation",
    "controller",
    "sweep",
    "viewer",
]

# ---------------------------------------------------------------- HTML
html_theme = "furo"
html_title = f"orthoglide-pin {release}"
html_static_path = ["_static"]
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
html_theme_options = {
    "source_repository": "",
    "navigation_with_keys": True,
}

# Options are written as typed: ``--static``, never an en dash.
smartquotes = False


def _notebook_outputs_in_build(app: object) -> None:
    """Keep the executed notebooks' files beside the doctrees (``build/``), not in the clone."""
    env = app.env  # type: ignore[attr-defined]
    folder = Path(app.doctreedir).parent / "jupyter_execute"  # type: ignore[attr-defined]
    env.mystnb_config = env.mystnb_config.copy(output_folder=str(folder.resolve()))


def setup(app: object) -> None:
    """Run after MyST-NB has made its configuration."""
    app.connect("builder-inited", _notebook_outputs_in_build, priority=900)  # type: ignore[attr-defined]
