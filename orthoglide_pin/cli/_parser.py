"""The command line's argument parser: one-line usage errors, defaults in ``--help``.

:class:`Parser` is the parser of ``orthoglide`` and of each sub-command: a
value that starts like a negative number (``-1e-3``, ``-0.05,0,0``) is never
an option, a usage error is one line with exit status 2, ``--help`` shows
every default (:class:`HelpFormatter`), and a path option refuses an empty
value (:func:`path_argument`). The other shared pieces of the command line
(parameters, numbers, output, errors) are in :mod:`orthoglide_pin.cli._common`.
"""

from __future__ import annotations

import argparse
import re
from collections.abc import Sequence
from typing import Any, NoReturn, TypeVar

from orthoglide_pin.cli._common import EXIT_ERROR
from orthoglide_pin.exceptions import MAX_VALUE_CHARS, one_line, short_repr

# Text that starts like a negative number is a value, never an option: ``-1e-3``,
# ``-.5``, ``-inf``, and lists such as ``-0.05,0,0`` or ``-0.1,0,0;0,0,0``.
_NEGATIVE_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)

_ActionT = TypeVar("_ActionT", bound=argparse.Action)
#: A value argparse quotes in a usage error (its ``repr``).
_QUOTED = re.compile(r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\"")
#: A usage error of an option given without its value.
_MISSING_VALUE = re.compile(r"^argument (\S+?)(?:/\S+)?: expected (?:one|at least one) argument")
#: Unrecognized arguments named in the usage error, at most.
MAX_SHOWN_EXTRAS = 5


def _plain(argument: str) -> str:
    """An argument as typed when short and plain, else quoted and cut (:func:`short_repr`)."""
    plain = argument.isprintable() and " " not in argument and len(argument) <= MAX_VALUE_CHARS
    return argument if plain and argument else short_repr(argument)


def _cut_quoted(match: re.Match[str]) -> str:
    """A quoted value of a usage error, cut as :func:`short_repr` cuts a value."""
    text = match.group(0)
    if len(text) <= MAX_VALUE_CHARS:
        return text
    return f"{text[: MAX_VALUE_CHARS - 4]}...{text[0]} ({len(text) - 2} characters)"


def has_default(action: argparse.Action) -> bool:
    """Whether an option has a default worth showing (not absent, off or empty)."""
    default = action.default
    return bool(action.option_strings) and not (
        default is None
        or default is False
        or default is argparse.SUPPRESS
        or (isinstance(default, (list, tuple)) and not default)
    )


def default_note(action: argparse.Action) -> str:
    """``(default: VALUE)`` of an option, ready for argparse's ``%`` formatting."""
    default = action.default
    shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) else default
    return f"(default: {str(shown).replace('%', '%%')})"


class HelpFormatter(argparse.HelpFormatter):
    """``--help`` that shows the default of every option that has one.

    An option whose help already says ``default`` keeps its own wording; a
    default of ``None``, ``False`` or an empty list (the option is simply
    absent) is not shown. Options taking three coordinates read ``X Y Z``
    even though they also accept one ``X,Y,Z`` word (``nargs="+"``).
    """

    def _get_help_string(self, action: argparse.Action) -> str:
        text = (action.help or "").strip()
        if not has_default(action) or "default" in text.lower():
            return text
        return f"{text} {default_note(action)}".strip()

    def _format_args(self, action: argparse.Action, default_metavar: str) -> str:
        if action.nargs == "+" and isinstance(action.metavar, tuple):
            return " ".join(action.metavar)
        return super()._format_args(action, default_metavar)


def is_path_option(action: argparse.Action) -> bool:
    """Whether an option takes one file or directory path (metavar ``FILE...`` or ``DIR``)."""
    metavar = action.metavar
    return (
        bool(action.option_strings)
        and action.nargs is None
        and isinstance(metavar, str)
        and (metavar.startswith("FILE") or metavar == "DIR")
    )


def path_argument(text: str) -> str:
    """A path option's value, refused when empty (``--static ""`` names no file).

    Raises:
        argparse.ArgumentTypeError: On an empty value (argparse makes it one line, exit 2).
    """
    if not text:
        raise argparse.ArgumentTypeError("an empty path: give a file or directory name")
    return text


class Parser(argparse.ArgumentParser):
    """Argument parser of ``orthoglide`` and its sub-commands.

    * ``-1e-3``, ``-.5`` or ``-0.05,0,0`` are values, not options;
    * a usage error is one line, ``orthoglide CMD: error: ...`` (exit 2), and
      the usage is shown by ``--help`` only;
    * ``--help`` shows every default (:class:`HelpFormatter`);
    * a path option (metavar ``FILE...`` or ``DIR``) refuses an empty value,
      which would otherwise read as "not given" (``view --static ""`` would serve).
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def _add_action(self, action: _ActionT) -> _ActionT:
        if action.help is None and has_default(action):
            action.help = default_note(action)  # argparse shows no line at all for None
        if action.type is None and is_path_option(action):
            action.type = path_argument
        return super()._add_action(action)

    def parse_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> argparse.Namespace:
        """As argparse's, but unknown arguments are reported by their sub-command."""
        parsed, extras = self.parse_known_args(args, namespace)
        if extras:
            where: argparse.ArgumentParser = self
            for action in self._actions:
                if isinstance(action, argparse._SubParsersAction):
                    where = action.choices.get(str(getattr(parsed, action.dest, "")), self)
            shown = " ".join(_plain(extra) for extra in extras[:MAX_SHOWN_EXTRAS])
            more = (
                f" and {len(extras) - MAX_SHOWN_EXTRAS} more"
                if len(extras) > MAX_SHOWN_EXTRAS
                else ""
            )
            where.error(f"unrecognized arguments: {shown}{more}")
        return parsed

    def _with_choices(self, message: str) -> str:
        """``message``, with the names an option takes when its value is missing.

        ``plan --example`` without a name: ``argument --example: expected one
        argument (one of pocket, contour, helix)``.
        """
        missing = _MISSING_VALUE.match(message)
        if missing is None:
            return message
        for action in self._actions:
            if missing.group(1) in action.option_strings and action.choices:
                return f"{message} (one of {', '.join(map(str, action.choices))})"
        return message

    def error(self, message: str) -> NoReturn:
        """Print one line ``PROG: error: MESSAGE`` on stderr and exit with status 2.

        A value argparse quotes (``invalid float value: '...'``) is cut to
        :data:`~orthoglide_pin.exceptions.MAX_VALUE_CHARS` characters and the
        line escaped (:func:`~orthoglide_pin.exceptions.one_line`).
        """
        line = one_line(" ".join(_QUOTED.sub(_cut_quoted, self._with_choices(message)).split()))
        self.exit(EXIT_ERROR, f"{self.prog}: error: {line} (see {self.prog} --help)\n")
