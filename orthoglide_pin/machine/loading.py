"""Loading a URDF into Pinocchio without losing anything silently.

urdfdom, the URDF parser under :func:`pinocchio.buildModelFromXML`, prints its
complaints on the process's standard error and carries on: an inertial element
it cannot parse (a mass of ``inf`` from an overflowing density, say) is dropped
and leaves a massless body, so every dynamic result would be wrong with no
error. :func:`load_model` captures that output and compares the loaded masses
with the URDF's own inertial elements.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from typing import Final

import pinocchio as pin

from orthoglide_pin.exceptions import DescriptionError

#: Most bytes kept from what the URDF parser prints while loading.
_MAX_CAPTURE: Final[int] = 65536
#: Relative tolerance between Pinocchio's total mass and the URDF's.
MASS_RTOL: Final[float] = 1e-9


def load_model(urdf: str) -> pin.Model:
    """Build the Pinocchio model of a URDF string, checking its masses.

    Args:
        urdf: The URDF text.

    Returns:
        The Pinocchio model (a tree).

    Raises:
        DescriptionError: The text is not a URDF Pinocchio can load, or a mass
            is not finite, or Pinocchio's masses differ from the URDF's
            (naming the link or the totals, and what the parser said).
    """
    if not isinstance(urdf, str):
        raise DescriptionError(f"urdf must be a URDF string, not {type(urdf).__name__}", urdf)
    with _captured_stderr() as parser_messages:
        try:
            model = pin.buildModelFromXML(urdf)
        except Exception as exc:  # Pinocchio raises ValueError/RuntimeError on bad XML
            raise DescriptionError(f"Pinocchio could not load the URDF: {exc}") from exc
    _check_masses(urdf, model, parser_messages)
    return model


@contextlib.contextmanager
def _captured_stderr() -> Iterator[list[str]]:
    """Collect what C++ libraries (urdfdom) print on file descriptor 2 meanwhile.

    Yields a list that holds the captured lines once the block ends; they never
    reach the user's terminal. A no-op where descriptor 2 cannot be duplicated.
    """
    lines: list[str] = []
    try:
        saved = os.dup(2)
    except OSError:
        yield lines
        return
    with tempfile.TemporaryFile() as sink:
        try:
            sys.stderr.flush()
            os.dup2(sink.fileno(), 2)
            yield lines
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)
            text = sink.read(_MAX_CAPTURE).decode("utf-8", "replace")
            lines.extend(line.strip() for line in text.splitlines() if line.strip())


def _check_masses(urdf: str, model: pin.Model, parser_messages: list[str]) -> None:
    """Refuse a model whose masses differ from the URDF's inertial elements.

    urdfdom drops an inertial element it cannot parse (a mass of ``inf`` from
    an overflowing density, say) with a message on stderr only, leaving a
    massless body. Every ``<mass value>`` must be a finite non-negative number,
    the parser must not have reported an error, and Pinocchio's total mass must
    equal their sum (relative ``MASS_RTOL``).

    Raises:
        DescriptionError: Naming the first bad link, or both totals, and what
            the URDF parser said.
    """
    said = f" (the URDF parser said: {parser_messages[0][:200]})" if parser_messages else ""
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError as exc:
        raise DescriptionError(f"the URDF is not valid XML: {exc}") from None
    total = 0.0
    for link in root.iter("link"):
        mass_el = link.find("inertial/mass")
        if mass_el is None:
            continue
        text = mass_el.get("value", "")
        try:
            mass = float(text)
        except ValueError:
            mass = math.nan
        if not (math.isfinite(mass) and mass >= 0.0):
            raise DescriptionError(
                f"link {link.get('name')!r} has mass {text[:40]!r} in the URDF, not a finite "
                f"number >= 0 [kg]: check density and the masses of the parameters{said}",
                text,
            )
        total += mass
    errors = [line for line in parser_messages if line.lower().startswith("error")]
    if errors:  # urdfdom goes on after an error, without the element it could not read
        raise DescriptionError(
            f"the URDF parser dropped part of the URDF: {' '.join(errors)[:300]}", errors
        )
    loaded = float(sum(inertia.mass for inertia in model.inertias))
    if not math.isclose(loaded, total, rel_tol=MASS_RTOL, abs_tol=1e-12):
        raise DescriptionError(
            f"Pinocchio loaded {loaded:.6g} kg of the URDF's {total:.6g} kg: some inertial "
            f"elements were dropped{said}",
            loaded,
        )
