"""The package's layout: one subpackage per layer, imports downward only, no circles.

Every import is read from the source (module level, inside functions and under
``TYPE_CHECKING`` alike), so a lazy import cannot hide an upward arrow.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import orthoglide_pin as og

PACKAGE = Path(og.__file__).resolve().parent
#: Each layer's tier: a layer may import its own tier and those below.
TIERS = {
    "machine": 0,
    "kinematics": 0,
    "kinetostatics": 1,
    "calibration": 1,
    "dynamics": 2,
    "motion": 2,
    "drives": 2,
    "program": 2,
    "elasticity": 3,
    "planning": 3,
    "controller": 4,
    "machining": 4,
    "report": 4,
    "simulation": 4,
    "sweep": 4,
    "viewer": 4,
    "cli": 5,
}
#: Shared plumbing at the root, importable from any layer.
PLUMBING = {
    "__init__",
    "__main__",
    "exceptions",
    "_io",
    "_outdir",
    "_paths",
    "_validation",
    "_lazy",
    "_compiled",
}
#: The test suite that crosses every layer (careless and hostile input).
CROSS_CUTTING = "hostile"
#: The core never reaches these.
OUTPUT_LAYERS = {"report", "sweep", "viewer", "cli"}
MAX_LINES = 450


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        out[".".join(("orthoglide_pin", *parts))] = path
    return out


def _imports(path: Path) -> Iterator[str]:
    """Dotted names of the package's modules imported anywhere in ``path``."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module.startswith("orthoglide_pin"):
                yield node.module
                for alias in node.names:  # ``from orthoglide_pin.x import module``
                    yield f"{node.module}.{alias.name}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("orthoglide_pin"):
                    yield alias.name


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in TIERS else None


def _graph() -> dict[str, set[str]]:
    modules = _modules()
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        targets = {t for t in _imports(path) if t in modules or t + ".__init__" in modules}
        graph[name] = {t if t in modules else t + ".__init__" for t in targets} - {name}
    return graph


def test_the_root_holds_only_plumbing() -> None:
    root_modules = {p.stem for p in PACKAGE.glob("*.py")}
    assert root_modules == PLUMBING
    layers = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    assert layers == set(TIERS)


def test_every_layer_says_what_it_is_for_and_exports_its_names() -> None:
    for layer in TIERS:
        path = PACKAGE / layer / "__init__.py"
        tree = ast.parse(path.read_text())
        assert ast.get_docstring(tree), layer
        if layer != "cli":
            names = [n for n in tree.body if isinstance(n, ast.Assign)]
            assert any(getattr(n.targets[0], "id", "") == "__all__" for n in names), layer


def test_imports_run_downward_only() -> None:
    upward = []
    for module, targets in _graph().items():
        source = _layer(module)
        for target in targets:
            dest = _layer(target)
            if source is None or dest is None:
                continue
            if TIERS[dest] > TIERS[source]:
                upward.append(f"{module} -> {target}")
    assert upward == []


def test_the_core_never_imports_the_outputs() -> None:
    offending = [
        f"{module} -> {target}"
        for module, targets in _graph().items()
        if _layer(module) not in OUTPUT_LAYERS | {None}
        for target in targets
        if _layer(target) in OUTPUT_LAYERS
    ]
    assert offending == []


def test_no_import_circles() -> None:
    graph = _graph()
    # A package's __init__ re-exports its modules: an arrow into a package from
    # one of its own modules is not a dependency of the layer on itself.
    for module, targets in graph.items():
        graph[module] = {
            t
            for t in targets
            if not (t.endswith(".__init__") and module.startswith(t.removesuffix("__init__")))
        }
    state: dict[str, int] = {}
    stack: list[str] = []
    circles: list[list[str]] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                circles.append([*stack[stack.index(nxt) :], nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert circles == []


def test_no_module_is_too_long() -> None:
    long = {
        str(path.relative_to(PACKAGE)): n
        for path in PACKAGE.rglob("*.py")
        if (n := len(path.read_text().splitlines())) > MAX_LINES
    }
    assert long == {}


def test_tests_mirror_the_layout() -> None:
    tests = Path(__file__).resolve().parent
    for layer in TIERS:
        assert (tests / layer).is_dir(), layer
    for path in tests.rglob("test_*.py"):
        if path.parent == tests or path.parent.name == CROSS_CUTTING:
            continue
        layer = path.parent.name
        assert layer in TIERS, path
        stem = path.stem.removeprefix("test_")
        module = PACKAGE / layer / f"{stem}.py"
        assert module.is_file() or stem in {"main", "browser", "viewer"}, path


def test_machining_never_imports_the_simulation() -> None:
    """A simulated contour error reaches the machining layer as an array, never by import."""
    offending = [
        f"{module} -> {target}"
        for module, targets in _graph().items()
        if _layer(module) == "machining"
        for target in targets
        if _layer(target) == "simulation"
    ]
    assert offending == []
