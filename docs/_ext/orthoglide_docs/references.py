"""Cross-references: public entries for module paths, code for objects without a page."""

from __future__ import annotations

import ast
import builtins
import importlib
import inspect
import re
import sys
from typing import Any

from docutils import nodes
from sphinx import addnodes
from sphinx.application import Sphinx

from orthoglide_docs._common import PACKAGE


def _exists(target: str) -> bool:
    """Whether a dotted name names an importable object."""
    if hasattr(builtins, target):
        return True
    parts = target.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        except Exception:  # a module that fails to import names nothing here
            return False
        for attr in parts[cut:]:
            if not hasattr(obj, attr):
                annotations = getattr(obj, "__annotations__", {})
                fields = getattr(obj, "__dataclass_fields__", {})
                return bool(attr in annotations or attr in fields)
            obj = getattr(obj, attr)
        return True
    return False


def _imports(module: str) -> dict[str, str]:
    """Names bound by the imports of a module (``TYPE_CHECKING`` ones too): name -> dotted."""
    try:
        source = inspect.getsource(importlib.import_module(module))
    except (OSError, TypeError, ImportError):
        return {}
    out: dict[str, str] = {}
    package = module if module.count(".") == 0 else module.rsplit(".", 1)[0]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname:
                    out[alias.asname] = alias.name
                else:
                    out[alias.name.split(".")[0]] = alias.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            for alias in node.names:
                out[alias.asname or alias.name] = f"{base}.{alias.name}"
    return out


def _object(dotted: str) -> list[Any]:
    """The objects along a dotted path inside the package (module, class, member)."""
    parts = dotted.split(".")
    objs: list[Any] = []
    obj: Any = importlib.import_module(PACKAGE)
    for part in parts[1:] if parts[0] == PACKAGE else parts:
        obj = (
            inspect.getattr_static(obj, part, None)
            if inspect.isclass(obj)
            else getattr(obj, part, None)
        )
        if obj is None:
            break
        objs.append(obj)
    return objs


def _context(node: Any) -> list[str]:
    """Modules in whose namespace a reference was written (most specific first)."""
    out: list[str] = []
    match = re.search(r"docstring of ([\w.]+)", str(node.source or ""))
    if match:
        parts = match.group(1).split(".")
        out += [".".join(parts[:k]) for k in range(len(parts), 0, -1)]
    desc = node
    while desc is not None and not isinstance(desc, addnodes.desc):
        desc = desc.parent
    if desc is not None:
        for sig in desc.findall(addnodes.desc_signature):
            dotted = ".".join(filter(None, [sig.get("module"), sig.get("fullname")]))
            for obj in reversed(_object(dotted)):
                target = obj.fget if isinstance(obj, property) else obj
                name = getattr(inspect.getmodule(target), "__name__", None)
                if name and name not in out:
                    out.append(name)
            break
    module = node.get("py:module")
    if module and module not in out:
        out.append(module)
    return [m for m in out if m.split(".")[0] == PACKAGE]


def _candidates(target: str, node: Any) -> list[str]:
    """Dotted names a reference may mean, given where it was written."""
    out = [target]
    head, _, rest = target.partition(".")
    for module in _context(node):
        bound = _imports(module).get(head)
        if bound:
            out.append(f"{bound}.{rest}" if rest else bound)
        out.append(f"{module}.{target}")
    if target.isidentifier():  # a bare name: the module of the package that defines it
        for name, module in sorted(sys.modules.items()):
            obj = getattr(module, target, None) if name.startswith(f"{PACKAGE}.") else None
            if obj is not None and getattr(obj, "__module__", None) == name:
                out.append(f"{name}.{target}")
                break
    return out


def resolve_missing(
    app: Sphinx, env: Any, node: Any, contnode: nodes.Element
) -> nodes.Element | None:
    """Public entries for module paths; code for objects without a page."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"]
    if target in app.config.autodoc_type_aliases or target in {"Ellipsis", "NoneType"}:
        return contnode
    candidates = _candidates(target, node)
    domain = env.domains["py"]
    public = set(importlib.import_module(PACKAGE).__all__)
    for cand in candidates:
        parts = cand.split(".")
        if parts[0] != PACKAGE:
            continue
        for k in range(1, len(parts)):
            if parts[k] in public:
                alias = ".".join([PACKAGE, *parts[k:]])
                if alias != cand or cand != target:
                    for role in (node["reftype"], "obj"):
                        found = domain.resolve_xref(
                            env, node["refdoc"], app.builder, role, alias, node, contnode
                        )
                        if found is not None:
                            return found
                break
    if any(_exists(c) for c in candidates):
        return contnode
    return None


_FORWARD_REF = re.compile(r"TypeAliasForwardRef\('([^']*)'\)")


def fix_signature(
    app: Sphinx,
    what: str,
    name: str,
    obj: Any,
    options: Any,
    signature: str | None,
    ret: str | None,
) -> tuple[str | None, str | None]:
    """Show type aliases by name (not ``TypeAliasForwardRef('X')``) and factories as ``...``."""

    def fix(text: str | None) -> str | None:
        if text is None:
            return None
        # a dataclass field with a default factory shows ``<factory>``, which no
        # signature parser reads
        return _FORWARD_REF.sub(r"\1", text).replace("<factory>", "...")

    return fix(signature), fix(ret)


def no_inline_type(
    app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    """Give back a property's first line: ``Mass [kg]: the ...`` is text, not ``TYPE: text``.

    Napoleon reads the first line of an attribute's docstring as ``TYPE:
    DESCRIPTION`` and moves ``TYPE`` into a ``:type:`` field; the types here come
    from the annotations, so the text goes back where it was written.
    """
    if what not in ("attribute", "property") or not lines:
        return
    last = next((i for i in range(len(lines) - 1, -1, -1) if lines[i].strip()), None)
    if last is None or not lines[last].startswith(":type: "):
        return
    head = lines[last].removeprefix(":type: ")
    del lines[last]
    while lines and not lines[-1].strip():
        lines.pop()
    first = next((i for i, line in enumerate(lines) if line.strip()), None)
    if first is None:
        lines.append(head)
    else:
        lines[first] = f"{head}: {lines[first].lstrip()}"
