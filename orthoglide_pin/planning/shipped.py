"""The example part programs shipped with the package.

The wheel carries, in ``orthoglide_pin/planning/examples/``, programs
(:mod:`orthoglide_pin.planning.gcode`) that fit the prototype's 200 mm cube
around home, written in the part's frame (program Z up, so their plunges go
into the part, towards the table), to plan as they are or to copy and edit
(``orthoglide plan --example pocket > pocket.nc``):

* ``pocket``: a zig-zag pocket of 80 x 60 mm, lines blended within 0.02 mm;
* ``contour``: a rounded rectangle of tangent lines and arcs, then a full circle
  and a dwell;
* ``helix``: a helix of radius 40 mm, five turns down 50 mm (G2 with Z).
"""

from __future__ import annotations

import importlib.resources
from importlib.abc import Traversable
from typing import Final

from orthoglide_pin._validation import choice

#: The shipped programs: name -> file name in ``orthoglide_pin/planning/examples/``.
EXAMPLE_PROGRAMS: Final = {
    "pocket": "pocket.nc",
    "contour": "contour.nc",
    "helix": "helix.nc",
}


def example_program_file(name: str) -> Traversable:
    """The shipped program ``name`` (a resource of the package).

    Raises:
        InvalidParameterError: ``name`` is not one of :data:`EXAMPLE_PROGRAMS`.
    """
    name = choice("name", name, EXAMPLE_PROGRAMS)  # one of the shipped programs
    return (
        importlib.resources.files("orthoglide_pin.planning") / "examples" / EXAMPLE_PROGRAMS[name]
    )


def example_program_text(name: str) -> str:
    """The text of the shipped program ``name``."""
    return example_program_file(name).read_text(encoding="utf-8")
