"""The design digest: which machine a file was made for.

A calibration, a planned trajectory or a simulated run belongs to one machine:
applied to another, it commands the wrong slider values or draws the wrong
motion. Each such file records the **design digest** of the machine it was
made for (:func:`design_digest`), and every reader refuses it, in one line
naming both digests (:class:`~orthoglide_pin.exceptions.DesignMismatchError`),
when it is given another design (:func:`check_design`).

The digest covers the parameters that place the mechanism's joints and its
tool, and the slider values allowed (:data:`DESIGN_FIELDS`): the leg length,
the parallelogram width, the carriage, platform and tool offsets and the slider
limits (as numbers: derived or given, the same limits give the same digest).
The other parameters (the drawing's sizes, the materials, the masses, the
stiffnesses, the CAD files, the cube and the criterion) change the drawing,
the dynamics or the judgement, not where the tool is for given slider values,
so a new spindle mass keeps the calibration.

The digest is documented so that it can be computed elsewhere: each value in
whole nanometres (``round(value / 1e-9)``, :data:`DIGEST_QUANTUM`, so that the
last bits of a float, a YAML round trip or limits derived again do not change
it), written ``name=N`` (a vector ``name=N1,N2,N3``) in the order of
:data:`DESIGN_FIELDS`, joined by ``;`` after the prefix ``orthoglide-design-1``;
the digest is the first :data:`DIGEST_LENGTH` hexadecimal digits of the
SHA-256 of that UTF-8 text. The prototype's is :func:`design_digest` ``()``.

A file written before the design was recorded has none: it is refused, with
the line to add if it was made for this design (:func:`check_design`). A
calibration commands a real machine's sliders: a warning is easily missed (the
command line shows none, and a program may filter them), while the line to add
costs one edit, once, and states the machine on purpose.
"""

from __future__ import annotations

import hashlib
import math
import re
from typing import TYPE_CHECKING, Final

from orthoglide_pin._validation import instance_of, positive_length
from orthoglide_pin.exceptions import DesignMismatchError, InvalidParameterError
from orthoglide_pin.machine.coerce import as_params

if TYPE_CHECKING:
    from orthoglide_pin.machine.params import OrthoglideParams

#: The parameters the digest covers, in the order they are hashed.
DESIGN_FIELDS: Final[tuple[str, ...]] = (
    "leg_length",
    "parallelogram_width",
    "carriage_offset",
    "platform_offset",
    "tool_offset",
    "slider_lower",
    "slider_upper",
)
#: Resolution of the values hashed [m]: each is rounded to whole nanometres.
DIGEST_QUANTUM: Final[float] = 1e-9
#: Hexadecimal digits of a digest.
DIGEST_LENGTH: Final[int] = 16
#: The text hashed starts with this (its ``1`` is the rule's version).
DIGEST_PREFIX: Final[str] = "orthoglide-design-1"
#: The first line of a CSV file that records its design: ``# orthoglide design: DIGEST``.
CSV_DESIGN_PREFIX: Final[str] = "# orthoglide design:"
#: Longest leg length a design line may record [m] (the kinematics' longest length).
MAX_LEG_LENGTH: Final[float] = 1000.0

_DIGEST = re.compile(rf"[0-9a-f]{{{DIGEST_LENGTH}}}")
_CSV_LINE = re.compile(
    r"#\s*orthoglide design:\s*(?P<digest>\S+?)\s*(?:,\s*leg_length:\s*(?P<leg>\S+)\s*)?"
)


def _params(params: OrthoglideParams | None) -> OrthoglideParams:
    return as_params(params)


def design_text(params: OrthoglideParams | None = None) -> str:
    """The text whose SHA-256 gives the digest (see the module), e.g. for a record.

    Args:
        params: The design; the prototype when ``None``.
    """
    p = _params(params)
    items = []
    for name in DESIGN_FIELDS:
        value = getattr(p, name)
        values = value if isinstance(value, tuple) else (value,)
        items.append(f"{name}=" + ",".join(str(round(v / DIGEST_QUANTUM)) for v in values))
    return ";".join((DIGEST_PREFIX, *items))


def design_digest(params: OrthoglideParams | None = None) -> str:
    """The design digest of a machine: 16 hexadecimal digits (see the module).

    Equal designs have equal digests, whatever parameters outside
    :data:`DESIGN_FIELDS` hold, and a design saved to YAML and read back keeps
    its digest.

    Args:
        params: The design; the prototype when ``None``.

    Returns:
        The digest, e.g. ``og.design_digest(og.prototype())``.
    """
    text = design_text(params)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:DIGEST_LENGTH]


def checked_digest(where: str, value: object) -> str:
    """``value`` if it is a digest (16 lowercase hexadecimal digits), else an error."""
    if not isinstance(value, str) or not _DIGEST.fullmatch(value):
        raise InvalidParameterError(
            where, value, f"a design digest: {DIGEST_LENGTH} hexadecimal digits (og.design_digest)"
        )
    return value


def _mm(length: float) -> str:
    return f"{1e3 * length:.6g} mm"


def check_design(
    recorded: str | None,
    params: OrthoglideParams | None,
    what: str,
    *,
    leg_length: float | None = None,
    line: str = 'design: "{digest}"',
    redo: str = "make it again for this design",
) -> None:
    """Refuse a file made for another design than ``params``, in one line naming both.

    Args:
        recorded: The digest the file records, or ``None`` when it records none.
        params: The design it is given with; the prototype when ``None``.
        what: The file, as the user knows it (its path, or ``"the calibration"``).
        leg_length: The leg length the file records [m], named in the message
            when it differs from the design's; ``None`` when unknown.
        line: The line that records the design in this kind of file, with
            ``{digest}`` for the digest (named when the file records none).
        redo: How to make the file again for this design.

    Raises:
        DesignMismatchError: The digests differ, or the file records none.
        InvalidParameterError: ``recorded`` is not a digest, or another argument
            is of the wrong kind.
    """
    p = _params(params)
    if recorded is not None:
        checked_digest("recorded", recorded)
    for name, text in (("what", what), ("line", line), ("redo", redo)):
        instance_of(name, text, str, "a text")
    if leg_length is not None:
        leg_length = positive_length("leg_length", leg_length)
    expected = design_digest(p)
    if recorded is not None and recorded == expected:
        return
    what = what if what.isprintable() else repr(what)  # one line, whatever the path holds
    known = leg_length is not None and abs(leg_length - p.leg_length) > DIGEST_QUANTUM
    if recorded is None and not known:
        raise DesignMismatchError(
            what,
            None,
            expected,
            f"{what} records no design (it was written before designs were recorded): if it "
            f"was made for this design ({expected}, leg length {_mm(p.leg_length)}), add the "
            f"line {line.replace('{digest}', expected)}; otherwise {redo}",
        )
    theirs = f" (leg length {_mm(leg_length)})" if known and leg_length is not None else ""
    ours = f" (leg length {_mm(p.leg_length)})" if known else ""
    if leg_length is not None and not known:  # the same legs: say so, and where to look
        ours = f" (the same leg length {_mm(p.leg_length)}: another of og.DESIGN_FIELDS differs)"
    made = "another design" if recorded is None else f"design {recorded}"
    raise DesignMismatchError(
        what,
        recorded,
        expected,
        f"{what} was made for {made}{theirs}, not this design {expected}{ours}: "
        f"give the design it was made for (--config, --param), or {redo}",
    )


def design_comment(params: OrthoglideParams | None = None) -> str:
    """The first line of a CSV file of this design, newline included.

    ``# orthoglide design: DIGEST, leg_length: L`` (L in metres, for the messages).
    """
    p = _params(params)
    return f"{CSV_DESIGN_PREFIX} {design_digest(p)}, leg_length: {p.leg_length!r}\n"


def read_design_comment(first_line: str, where: str) -> tuple[str, float | None] | None:
    """The digest and the leg length [m] of a CSV's first line, ``None`` if it records none.

    Raises:
        InvalidParameterError: A design line whose digest or leg length is malformed.
    """
    text = first_line.strip()
    if not text.startswith("#") or "orthoglide design:" not in text:
        return None
    match = _CSV_LINE.fullmatch(text)
    if match is None:
        raise InvalidParameterError(where, text, f"a first line '{CSV_DESIGN_PREFIX} DIGEST'")
    digest = checked_digest(where, match["digest"].rstrip(","))
    if match["leg"] is None:
        return digest, None
    try:
        leg = float(match["leg"])
    except ValueError:
        leg = math.nan
    if not (math.isfinite(leg) and 0.0 < leg <= MAX_LEG_LENGTH):
        raise InvalidParameterError(where, match["leg"], "a leg length in metres")
    return digest, leg
