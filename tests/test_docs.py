"""The documentation site builds strictly and is complete.

The site is built once per test run, as ``make docs`` builds it (the same
strict options, read from the Makefile: warnings are errors, every reference
must resolve), into a temporary folder, from a copy of ``docs/`` whose
notebooks are the copies the notebook tests have just executed. Then:

* every name of ``orthoglide_pin.__all__`` has its entry in the API reference,
  with a description;
* every command of ``orthoglide`` has its section in the command-line
  reference, and every option and argument of every command its entry;
* the notebooks are rendered with their figures.

The checks walk the package and the parsers, so a new name, command or option
is caught without a change here.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import inspect
import re
import shutil
import subprocess
import sys
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from _notebooks import NotebookRuns
from test_layers import TIERS

import orthoglide_pin as og
from orthoglide_pin.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: The program name of the options every command takes (docs/_ext/orthoglide_docs/cli.py).
EVERY_COMMAND = "COMMAND"
#: Seconds allowed for the build (about a minute on a quiet machine).
BUILD_TIMEOUT = 1200

pytest.importorskip("sphinx")
pytest.importorskip("myst_nb")
nbformat = pytest.importorskip("nbformat")


def sphinx_options() -> list[str]:
    """The strict options of ``make docs`` (``SPHINXOPTS`` in the Makefile)."""
    match = re.search(r"^SPHINXOPTS \?= (.+)$", (ROOT / "Makefile").read_text(), re.MULTILINE)
    assert match, "SPHINXOPTS is not set in the Makefile"
    return match.group(1).split()


@dataclass
class Site:
    """A built site: its folder, the build's log and its inventory of objects."""

    out: Path
    log: str
    inventory: dict[str, tuple[str, str]]  # name -> (domain:role, page#anchor)

    def page(self, relative: str) -> str:
        return (self.out / relative).read_text()


def read_inventory(path: Path) -> dict[str, tuple[str, str]]:
    """Sphinx's ``objects.inv`` (version 2): object name -> (domain:role, location)."""
    raw = path.read_bytes()
    lines = raw.split(b"\n", 4)
    assert lines[0] == b"# Sphinx inventory version 2"
    body = zlib.decompress(lines[4]).decode()
    out = {}
    for line in body.splitlines():
        match = re.match(r"(.+?)\s+(\S+:\S+)\s+(-?\d+)\s+(\S+)\s+(.*)", line)
        if match:
            name, role, _, location, _ = match.groups()
            out[f"{role} {name}"] = (role, location.replace("$", name))
    return out


@pytest.fixture(scope="module")
def site(notebook_runs: NotebookRuns, tmp_path_factory: pytest.TempPathFactory) -> Site:
    """The site, built strictly from the executed notebooks."""
    tree = tmp_path_factory.mktemp("docs-tree")
    shutil.copytree(DOCS, tree / "docs", symlinks=True, ignore=shutil.ignore_patterns("api"))
    shutil.copy(ROOT / "CHANGELOG.md", tree / "CHANGELOG.md")
    (tree / "notebooks").mkdir()
    for name in notebook_runs.names():
        nbformat.write(notebook_runs.get(name).book, tree / "notebooks" / name)
    out, doctrees = tree / "site", tree / "build" / "doctrees"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-b",
            "html",
            *sphinx_options(),
            "-d",
            str(doctrees),
            "-D",
            "nb_execution_mode=off",
            str(tree / "docs"),
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=BUILD_TIMEOUT,
    )
    log = done.stdout + done.stderr
    assert done.returncode == 0, log[-20_000:]
    return Site(out, log, read_inventory(out / "objects.inv"))


def test_the_build_is_strict_and_clean(site: Site) -> None:
    options = sphinx_options()
    assert "-W" in options and "-n" in options  # warnings are errors, references checked
    assert "WARNING" not in site.log and "ERROR" not in site.log
    assert (site.out / "index.html").is_file()
    # A static site: no page links to a server of its own.
    assert "http://127.0.0.1" not in site.page("index.html")


#: ``make docs`` executes a notebook as myst-nb does, after the site's extension has run.
_KERNEL_SCRIPT = """
import sys
sys.path.insert(0, sys.argv[1])
import logging
logging.basicConfig(level=logging.INFO)  # as a Pygments plugin of the theme does on import
from orthoglide_docs.kernel import ipc_kernels, quiet_root_logger
ipc_kernels(None)
quiet_root_logger(None)
import nbformat
from jupyter_cache.executors.utils import single_nb_execution
nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("print(6 * 7)")])
result = single_nb_execution(nb, cwd=sys.argv[2], allow_errors=False, timeout=60)
assert result.err is None, result.err
print(nb.cells[0].outputs[0]["text"].strip())
"""


#: libzmq's own line when a kernel's sockets close while it is stopped (a race in
#: libzmq at the kernel's exit, seen rarely; the kernel had already answered).
_ZMQ_TEARDOWN = "Assertion failed: pfd.revents & POLLIN (src/signaler.cpp:238)"


def test_the_notebooks_of_the_build_run_silently(tmp_path: Path) -> None:
    pytest.importorskip("jupyter_cache")
    done = subprocess.run(
        [sys.executable, "-c", _KERNEL_SCRIPT, str(DOCS / "_ext"), str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-5000:]
    assert done.stdout.strip() == "42"
    lines = [line for line in done.stderr.splitlines() if line != _ZMQ_TEARDOWN]
    assert lines == []  # no kernel warning (TCP), no INFO line


def _python_objects(site: Site) -> dict[str, str]:
    """Python objects of the inventory: full name -> page#anchor."""
    return {
        k.split(" ", 1)[1]: loc
        for k, (role, loc) in site.inventory.items()
        if role.startswith("py:")
    }


def test_every_public_name_has_an_api_entry(site: Site) -> None:
    objects = _python_objects(site)
    missing = [n for n in og.__all__ if f"orthoglide_pin.{n}" not in objects]
    outside = [
        n for n in og.__all__ if not objects.get(f"orthoglide_pin.{n}", "api/").startswith("api/")
    ]
    assert missing == [] and outside == []


def _entry_text(html: str, anchor: str) -> str:
    """The text of the description that follows the entry ``anchor`` on a page."""
    start = html.index(f'id="{anchor}"')
    dd = html.index("<dd>", start)
    end = html.index("</dd>", dd)
    return re.sub(r"<[^>]+>", "", html[dd:end]).strip()


def test_every_public_name_is_described(site: Site) -> None:
    objects = _python_objects(site)
    bare = []
    for name in og.__all__:
        page, _, anchor = objects[f"orthoglide_pin.{name}"].partition("#")
        if not _entry_text(site.page(page), anchor):
            bare.append(name)
    assert bare == []


def own_doc(obj: object) -> str:
    """A docstring of the object's own (not inherited, not the one dataclasses make up)."""
    if inspect.isclass(obj):
        doc = obj.__dict__.get("__doc__") or ""
        return "" if doc.startswith(f"{obj.__name__}(") else doc.strip()
    return (getattr(obj, "__doc__", None) or "").strip() if callable(obj) else "constant"


def test_every_public_class_and_function_has_a_docstring() -> None:
    assert [n for n in og.__all__ if not own_doc(getattr(og, n))] == []


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _names(action: argparse.Action) -> list[str]:
    if action.option_strings:
        return list(action.option_strings)
    metavar = action.metavar
    return list(metavar) if isinstance(metavar, tuple) else [str(metavar or action.dest)]


def test_every_command_and_option_is_in_the_cli_reference(site: Site) -> None:
    commands = _commands()
    options = {k.split(" ", 1)[1] for k in site.inventory if k.startswith("std:cmdoption ")}
    labels = {k.split(" ", 1)[1] for k in site.inventory if k.startswith("std:label ")}
    shared = {o.split(".", 1)[1] for o in options if o.startswith(f"orthoglide-{EVERY_COMMAND}.")}
    # What the reference shows once is an option of every command.
    for name in shared:
        assert all(
            any(name in a.option_strings for a in sub._actions) for sub in commands.values()
        ), name
    missing = []
    for command, sub in commands.items():
        if f"cli-{command}" not in labels:
            missing.append(command)
        for action in sub._actions:
            for name in _names(action):
                if f"orthoglide-{command}.{name}" not in options and name not in shared:
                    missing.append(f"{command} {name}")
    for action in build_parser()._actions:
        if action.option_strings and not isinstance(action, argparse._SubParsersAction):
            missing += [n for n in action.option_strings if f"orthoglide.{n}" not in options]
    assert missing == []
    page = site.page("reference/cli.html")
    for command, sub in commands.items():  # the usage as --help prints it
        first = sub.format_usage().split("\n")[0].split("[")[0].strip()
        assert first.removeprefix("usage: ") in page, command


def test_the_notebooks_are_rendered_with_their_figures(
    site: Site, notebook_runs: NotebookRuns
) -> None:
    for name in notebook_runs.names():
        html = site.page(f"notebooks/{Path(name).stem}.html")
        assert "<iframe srcdoc=" in html, name  # the scene
        images = re.findall(r'<img[^>]+src="([^"]+\.png)"', html)
        assert images, name
        for src in images:
            assert (site.out / "notebooks" / src).resolve().is_file(), (name, src)


def _extension() -> Any:
    """``docs/_ext/orthoglide_docs/``, the generator of the reference pages."""
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        return importlib.import_module("orthoglide_docs")
    finally:
        sys.path.pop(0)


def test_every_public_name_lands_on_exactly_one_api_page() -> None:
    groups, left = _extension().api_groups([])
    names = [n for g in groups for n in g.names] + left
    assert sorted(names) == sorted(og.__all__)
    assert left == ["__version__"]
    layers = {g.name for g in groups}
    assert set(TIERS) - {"cli"} <= layers  # every layer that exports names has its page


def test_a_name_without_a_docstring_is_found() -> None:
    ext = _extension()

    @dataclasses.dataclass
    class Bare:
        x: float

    def bare() -> None:
        pass

    @dataclasses.dataclass
    class Documented:
        """A documented thing."""

        x: float

    assert ext.own_doc(Bare) == "" and ext.own_doc(bare) == ""
    assert ext.own_doc(Documented) == "A documented thing."
    assert own_doc(Bare) == "" and own_doc(bare) == ""
