"""Exceptions raised by orthoglide-pin.

Every error derives from :class:`OrthoglideError` and carries the offending
value(s) as attributes, so callers can react programmatically and the command
line can print one clear line without a traceback.
"""

from __future__ import annotations

import os
import reprlib
from typing import Any

import numpy as np

#: Longest shown form of a bad value in an error message [characters]; the
#: whole value stays on the exception (``value``).
MAX_VALUE_CHARS = 80
#: Longest shown form of a file name [characters]: a longer one is cut in the
#: middle, so its beginning and its own name stay (:func:`path_repr`).
MAX_PATH_CHARS = 255
#: Longest shown name of a parameter [characters] (a dotted name built from a file's keys).
MAX_NAME_CHARS = 120
#: Longest error message [characters]: a last bound, should a message quote
#: more than its values (each value is already cut to :data:`MAX_VALUE_CHARS`).
MAX_MESSAGE_CHARS = 2000


def printable(text: str) -> str:
    r"""``text`` with every control or invisible character escaped (``\x00``, ``\n``).

    Spaces stay; a newline, a tab, a NUL, an escape sequence or a line
    separator become their Python escapes, so a message is one line of plain
    characters whatever a file or an argument held.
    """
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def path_repr(name: str | bytes, limit: int = MAX_PATH_CHARS) -> str:
    """``repr`` of a file name as given; a longer one than ``limit`` is cut in the middle.

    Its beginning and its end (the file's own name) stay, with the full length.
    """
    text = repr(name)
    if len(text) <= limit:
        return text
    half = max((limit - 5) // 2, 1)
    return f"{text[:half]}...{text[-half:]} ({len(name)} characters)"


def short_repr(value: Any, limit: int = MAX_VALUE_CHARS) -> str:
    """``repr(value)`` cut to ``limit`` characters (``...`` and the full length added).

    A huge value (an expanded YAML alias, a long string, a big array) then
    gives a one-line message; ``repr`` of numpy arrays is already summarised.
    Control characters are escaped (``repr`` of a string does it). A path
    (``os.PathLike``) is shown as the string the user gave, up to
    :data:`MAX_PATH_CHARS` (:func:`path_repr`).
    """
    if isinstance(value, os.PathLike):
        try:
            name = os.fspath(value)
        except Exception:  # a broken __fspath__ must not hide the error being reported
            return f"<{type(value).__name__}>"
        return path_repr(name)
    if isinstance(value, (str, bytes)) and len(value) > limit:
        unit = "characters" if isinstance(value, str) else "bytes"
        head = repr(value[: max(limit - 8, 1)])[:-1]
        return f"{head[: limit - 1]}... ({len(value)} {unit})"
    shortener = reprlib.Repr()
    shortener.maxstring = shortener.maxother = limit + 2
    shortener.maxlist = shortener.maxtuple = shortener.maxdict = 12
    try:
        text = shortener.repr(value)  # bounded work, even for huge containers
    except Exception:  # a broken __repr__ must not hide the error being reported
        text = f"<{type(value).__name__}>"
    text = printable(text.replace("\n", " "))
    if len(text) <= limit:
        return text
    return f"{text[: max(limit - 3, 1)]}... ({len(text)} characters)"


def cut_text(text: str, limit: int = MAX_VALUE_CHARS) -> str:
    """Another library's words (an exception's text) for a message: escaped, at most ``limit``.

    Unlike :func:`short_repr` the text is not quoted: it reads as part of the
    sentence, but it quotes no more of a file than a value may.
    """
    text = printable(" ".join(text.split()))
    return text if len(text) <= limit else f"{text[: max(limit - 3, 1)]}..."


def one_line(message: str, limit: int = MAX_MESSAGE_CHARS) -> str:
    """``message`` as one line: control characters escaped (a newline too), then cut.

    The last bound on any message shown (an exception's, a usage error's):
    at most ``limit`` characters, never a control character.
    """
    text = printable(message)
    if len(text) <= limit:
        return text
    return f"{text[: max(limit - 30, 1)]}... ({len(text)} characters)"


class Described:
    """A value shown in a message by a description (``<text of 12 characters>``), not quoted.

    For a value whose content a message must not show (:func:`short_repr`
    gives the description as it is).
    """

    def __init__(self, description: str) -> None:
        self.description = description

    def __repr__(self) -> str:
        return self.description


def _fmt_point(point: Any) -> str:
    """Format a point (or any small array) for an error message."""
    arr = np.asarray(point, dtype=float).ravel()
    return "(" + ", ".join(f"{v:.6g}" for v in arr) + ")"


class OrthoglideError(Exception):
    """Root of every error raised by orthoglide-pin.

    Attributes:
        value: The offending value, or ``None`` when there is no single one.
    """

    def __init__(self, message: str, value: Any = None) -> None:
        super().__init__(one_line(message))
        self.value = value


class InvalidParameterError(OrthoglideError, ValueError):
    """A machine parameter or an input value is out of its allowed range.

    Attributes:
        name: Name of the parameter or argument.
        value: The rejected value.
        allowed: Human-readable description of what is allowed.
    """

    def __init__(self, name: str, value: Any, allowed: str) -> None:
        label = str(name)
        shown = label if len(label) <= MAX_NAME_CHARS else f"{label[: MAX_NAME_CHARS - 3]}..."
        super().__init__(
            f"invalid {shown}={short_repr(value)}: expected {allowed}",
            value,
        )
        self.name = name
        self.allowed = allowed


class DescriptionError(OrthoglideError):
    """The machine description could not be rendered or loaded."""


class UnreachablePointError(OrthoglideError, ValueError):
    """A tool point lies outside the reach of a leg.

    Attributes:
        point: The tool point [m], shape (3,).
        leg: Index of the failing leg (1, 2 or 3).
        value: Same as ``point``.
    """

    def __init__(self, point: Any, leg: int, reason: str) -> None:
        self.point = np.asarray(point, dtype=float).copy()
        self.leg = leg
        super().__init__(
            f"point {_fmt_point(point)} m is unreachable by leg {leg}: {reason}", self.point
        )


class SingularConfigurationError(OrthoglideError, ValueError):
    """A configuration is (numerically) singular.

    Attributes:
        point: The tool point [m], shape (3,).
        leg: Index of the leg at fault (1, 2 or 3), or ``None`` for a parallel
            singularity that involves all legs.
        kind: ``"serial"`` or ``"parallel"``.
    """

    def __init__(self, point: Any, leg: int | None, kind: str, reason: str) -> None:
        self.point = np.asarray(point, dtype=float).copy()
        self.leg = leg
        self.kind = kind
        where = f"leg {leg}" if leg is not None else "all legs"
        super().__init__(
            f"point {_fmt_point(point)} m is a {kind} singularity ({where}): {reason}",
            self.point,
        )


class NoAssemblyError(OrthoglideError, ValueError):
    """No assembly of the closed loops exists for the given slider values.

    Attributes:
        q: The slider values [m], shape (3,).
        leg: Index of the leg that cannot close, or ``None`` when unknown.
        residual: Loop-closure residual reached by the solver [m, rad], or
            ``None`` when no solve was attempted.
    """

    def __init__(
        self,
        q: Any,
        reason: str,
        leg: int | None = None,
        residual: float | None = None,
    ) -> None:
        self.q = np.asarray(q, dtype=float).copy()
        self.leg = leg
        self.residual = residual
        super().__init__(f"no assembly for slider values {_fmt_point(q)} m: {reason}", self.q)


class PortInUseError(OrthoglideError):
    """A server cannot listen on its port: another program holds it.

    Attributes:
        host: The address the server tried to bind.
        port: The port that is in use.
        value: Same as ``port``.
    """

    def __init__(self, host: str, port: int, reason: str = "address already in use") -> None:
        self.host = host
        self.port = port
        super().__init__(
            f"port {port} on {host} is in use ({reason}): stop the program that holds it "
            "or choose another port (--port, 0 for any free port)",
            port,
        )


class NonFiniteResultError(OrthoglideError, ArithmeticError):
    """A result to be printed or saved is NaN or infinite.

    Raised instead of writing ``NaN`` or ``Infinity`` (which are not JSON):
    the inputs are too extreme or too close to a singularity for the result
    to be represented.

    Attributes:
        where: Which result, e.g. ``"J_inv[1][2]"``.
        value: The non-finite value.
    """

    def __init__(self, where: str, value: float) -> None:
        self.where = where
        super().__init__(
            f"the result {where} is {value}, not a finite number: the input is too "
            "extreme or too close to a singularity",
            value,
        )


class OutputPathError(OrthoglideError, OSError):
    """An output path cannot be written, or writing it would destroy something.

    Raised for a special file (FIFO, device, socket), an existing directory
    that the package did not write, or a path the system refuses. It is also
    an :class:`OSError`. The message names the path as the caller gave it,
    never a temporary file.

    Attributes:
        path: The path as given.
        reason: What is wrong, and the way out.
        value: Same as ``path``.
    """

    def __init__(self, path: Any, reason: str) -> None:
        self.path = str(path)
        self.reason = reason
        super().__init__(f"cannot write {path_repr(self.path)}: {reason}", self.path)


class MissingExtraError(OrthoglideError, ImportError):
    """A feature needs an optional package that is not installed.

    The message is one line naming the package and the extra that brings it,
    e.g. ``pip install 'orthoglide-pin[tables]'``.

    Attributes:
        module: The module that could not be imported.
        extra: The extra of ``orthoglide-pin`` that installs it.
        value: Same as ``module``.
    """

    def __init__(self, module: str, extra: str, feature: str = "this") -> None:
        self.module = module
        self.extra = extra
        OrthoglideError.__init__(
            self,
            f"{feature} needs the optional package {module}, which is not installed: "
            f"pip install 'orthoglide-pin[{extra}]'",
            module,
        )


class MissingExecutableError(OrthoglideError, FileNotFoundError):
    """A feature needs an external program that is not installed (not a pip package).

    The message is one line naming the program and the system package that
    installs it, e.g. LinuxCNC's ``rs274`` from Debian's ``linuxcnc-uspace``.

    Attributes:
        executable: The program that was not found.
        package: The system package that installs it.
        value: Same as ``executable``.
    """

    def __init__(self, executable: str, package: str, feature: str = "this") -> None:
        self.executable = executable
        self.package = package
        OrthoglideError.__init__(
            self,
            f"{feature} needs the program {short_repr(executable)}, which is not installed "
            f"or not on PATH: install {package}",
            executable,
        )


class CalibrationError(OrthoglideError, ValueError):
    """Measurements cannot calibrate the machine as asked.

    Raised for a measurement file that is malformed (a missing column, a
    non-finite value, values in millimetres, too few or duplicated rows) and
    for poses that cannot determine the geometry. The message is one line.

    Attributes:
        value: The offending value (a row, a column name, the combinations
            that the poses cannot determine), or ``None``.
    """


#: Longest reason of a :class:`ProgramError` [characters]: what it quotes of the
#: program is cut to :data:`MAX_VALUE_CHARS` (:func:`short_repr`) before.
MAX_REASON_CHARS = 400


class ProgramError(OrthoglideError, ValueError):
    """A part program (G-code) cannot be read or planned: one line naming its line.

    Attributes:
        line: Line number in the program (1 for the first line).
        reason: What is wrong at that line.
        value: Same as ``line``.
    """

    def __init__(self, line: int, reason: str) -> None:
        self.line = int(line)
        self.reason = one_line(reason, MAX_REASON_CHARS)
        super().__init__(f"program line {self.line}: {reason}", self.line)


class DesignMismatchError(OrthoglideError, ValueError):
    """A file made for one machine is given another: one line naming both designs.

    Raised when a calibration, a planned trajectory or a simulated run records
    another design digest (:func:`~orthoglide_pin.machine.digest.design_digest`)
    than the machine it is applied to, or records none (a file written before
    designs were recorded: the message gives the line to add).

    Attributes:
        what: The file (its path as given, or what it is).
        recorded: The digest the file records, or ``None`` when it records none.
        expected: The digest of the machine it was given with.
        value: Same as ``recorded``.
    """

    def __init__(self, what: str, recorded: str | None, expected: str, message: str) -> None:
        self.what = what
        self.recorded = recorded
        self.expected = expected
        super().__init__(message, recorded)


class CutConditionsError(InvalidParameterError):
    """Cutting conditions (a cut file, or their API values) are missing or out of range.

    One line naming the value (``tool.diameter``, ``engagement.lines``) and
    what is allowed; a value that a unit slip explains (a diameter of 10,
    meant in mm; a coefficient in N/mm^2) gets the value meant.

    Attributes:
        name: The value's name.
        value: The rejected value.
        allowed: What is allowed.
    """
