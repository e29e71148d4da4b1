"""The keys of a file, read from the dataclass that holds them and its docstring."""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

from orthoglide_docs._common import logger, parse_rst

_FIELD = re.compile(r"^    (\w+): (.*)$")


def attribute_docs(cls: type) -> dict[str, str]:
    """The ``Attributes:`` section of a Google-style class docstring, by name."""
    doc = inspect.getdoc(cls) or ""
    out: dict[str, str] = {}
    inside, name = False, None
    for line in doc.splitlines():
        if line.strip() == "Attributes:":
            inside = True
            continue
        if inside and line and not line.startswith(" "):
            break
        match = _FIELD.match(line) if inside else None
        if match:
            name = match.group(1)
            out[name] = match.group(2).strip()
        elif inside and name and line.strip():
            out[name] += " " + line.strip()
    return out


def _yaml_value(value: object) -> str:
    """A default as it is written in YAML."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_yaml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{}" if not value else repr(value)
    return f"{value:.12g}" if isinstance(value, float) else str(value)


def fields_table(cls: type) -> list[str]:
    """ReST table of a dataclass's public fields: key, default, meaning."""
    docs = attribute_docs(cls)
    lines = [
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 1 1 3",
        "",
        "   * - key",
        "     - default",
        "     - meaning",
    ]
    for f in dataclasses.fields(cls):
        if f.name.startswith("_"):
            continue
        if f.default is not dataclasses.MISSING:
            default = f"``{_yaml_value(f.default)}``"
        elif f.default_factory is not dataclasses.MISSING:
            default = f"``{_yaml_value(f.default_factory())}``"
        else:
            default = "(required)"
        text = docs.get(f.name)
        if not text:
            logger.warning(
                "%s.%s is not described in the class docstring's Attributes",
                cls.__qualname__,
                f.name,
                type="orthoglide",
                subtype="fields",
            )
        lines += [f"   * - ``{f.name}``", f"     - {default}", f"     - {text or ''}"]
    return [*lines, ""]


class FieldsTable(SphinxDirective):
    """``.. orthoglide-fields:: orthoglide_pin.Class``: the keys of a file, from a dataclass."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        """Parse the generated table."""
        module, _, name = self.arguments[0].rpartition(".")
        cls = getattr(importlib.import_module(module), name)
        return parse_rst(self, fields_table(cls), f"fields of {self.arguments[0]}")
