"""The command-line reference: every command and option, read from the argparse parsers."""

from __future__ import annotations

import argparse
import re
from collections.abc import Sequence

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

from orthoglide_docs._common import parse_rst, title

_CODE = re.compile(r"`([^`]+)`")


def rst_text(text: str) -> str:
    """Help text as reST: ```code``` stays code, markup characters are plain."""
    parts = _CODE.split(text)
    out = []
    for i, part in enumerate(parts):
        if i % 2:
            out.append(f"``{part}``")
        else:
            part = part.replace("\\", "\\\\").replace("*", "\\*").replace("|", "\\|")
            out.append(re.sub(r"_(?=\W|$)", r"\\_", part))
    return "".join(out)


def subcommands(parser: argparse.ArgumentParser) -> dict[str, tuple[argparse.ArgumentParser, str]]:
    """Each command's parser and one-line help, in the order of ``--help``."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help or "" for a in action._choices_actions}
            return {name: (sub, helps.get(name, "")) for name, sub in action.choices.items()}
    return {}


def common_options(parser: argparse.ArgumentParser) -> list[argparse.Action]:
    """The options every command takes (``--param``, ``--config``, ``--json``, ``-h``)."""
    commands = [sub for sub, _ in subcommands(parser).values()]
    if not commands:
        return []
    shared = set.intersection(*({tuple(a.option_strings) for a in c._actions} for c in commands))
    return [
        a for a in commands[0]._actions if a.option_strings and tuple(a.option_strings) in shared
    ]


def _options(
    parser: argparse.ArgumentParser,
    program: str,
    actions: list[argparse.Action] | None = None,
    skip: Sequence[argparse.Action] = (),
) -> list[str]:
    """``program`` and ``option`` entries of ``actions`` (default: the parser's, less ``skip``)."""
    formatter = parser._get_formatter()
    skipped = {tuple(a.option_strings) for a in skip}
    lines = [f".. program:: {program}", ""]
    for action in parser._actions if actions is None else actions:
        if isinstance(action, argparse._SubParsersAction):
            continue
        if action.option_strings and tuple(action.option_strings) in skipped:
            continue
        invocation = formatter._format_action_invocation(action)
        if not action.option_strings and isinstance(action.metavar, tuple):
            invocation = " ".join(action.metavar)
        text = formatter._expand_help(action) if action.help else ""
        if action.choices is not None and "%(choices)" not in (action.help or ""):
            text += " (one of: " + ", ".join(f"`{c}`" for c in action.choices) + ")"
        if action.required and action.option_strings:
            text += " (required)"
        lines += [f".. option:: {invocation}", "", f"   {rst_text(text.strip())}", ""]
    return lines


def _usage(parser: argparse.ArgumentParser) -> list[str]:
    usage = parser.format_usage().strip().splitlines()
    return [".. code-block:: text", "", *(f"   {u}" for u in usage), ""]


#: The program name of the options that every command takes.
EVERY_COMMAND = "COMMAND"


def cli_reference(parser: argparse.ArgumentParser) -> list[str]:
    """The reST of the whole command line: the program, the common options, each command."""
    prog = parser.prog
    commands = subcommands(parser)
    common = common_options(parser)
    lines = [
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 1 3",
        "",
        "   * - command",
        "     - what it does",
    ]
    for name, (_, help_) in commands.items():
        lines += [f"   * - :ref:`{prog} {name} <cli-{name}>`", f"     - {rst_text(help_)}"]
    lines += ["", f".. _cli-{prog}:", "", *title(f"``{prog}``", "-")]
    lines += [rst_text(parser.description or ""), "", *_usage(parser)]
    lines += _options(parser, prog)
    if common:
        lines += [".. _cli-every-command:", "", *title("Options of every command", "-")]
        names = ", ".join(f"``{a.option_strings[-1]}``" for a in common)
        lines += [f"Every command takes these ({names}):", ""]
        first = next(iter(commands.values()))[0]
        lines += _options(first, f"{prog} {EVERY_COMMAND}", common)
    for name, (sub, help_) in commands.items():
        lines += [f".. _cli-{name}:", "", *title(f"``{prog} {name}``", "-")]
        lines += [rst_text(help_[:1].upper() + help_[1:]) + ".", "", *_usage(sub)]
        if sub.description and sub.description.strip() != help_.strip():
            lines += [rst_text(" ".join(sub.description.split())), ""]
        if sub.epilog:
            lines += [rst_text(" ".join(sub.epilog.split())), ""]
        lines += _options(sub, f"{prog} {name}", skip=common)
        if common:
            lines += ["And the :ref:`options of every command <cli-every-command>`.", ""]
    return lines


class CliReference(SphinxDirective):
    """``.. orthoglide-cli::``: the reference of every command, from the parsers."""

    has_content = False

    def run(self) -> list[nodes.Node]:
        """Parse the generated reference."""
        from orthoglide_pin.cli import build_parser

        return parse_rst(self, cli_reference(build_parser()), "orthoglide --help")
