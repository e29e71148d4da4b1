"""The example drive files shipped with the package.

The wheel carries, in ``orthoglide_pin/drives/examples/``, drive files that
:func:`~orthoglide_pin.drives.motor.load_drive` reads (``drive_train`` and
``motor`` sections, SI units, motor speeds in rpm), to copy and edit:
``orthoglide drive --example > drive.yaml`` prints the prototype's.

* ``prototype``: the prototype's ball screws (lead 25 mm, direct drive) with an
  illustrative 400 W servo motor; every value is an assumption (the paper gives
  none).
"""

from __future__ import annotations

import importlib.resources
from importlib.abc import Traversable
from typing import Final

from orthoglide_pin._validation import choice

#: The shipped examples: name -> file name in ``orthoglide_pin/drives/examples/``.
EXAMPLE_DRIVES: Final = {"prototype": "prototype_drive.yaml"}
#: The example printed when no name is given.
DEFAULT_EXAMPLE: Final = "prototype"


def example_drive_file(name: str = DEFAULT_EXAMPLE) -> Traversable:
    """The shipped example drive file ``name`` (a resource of the package).

    ``str(example_drive_file())`` is a path on disk for an ordinary install, so
    it can be given to ``orthoglide report --motor``.

    Raises:
        InvalidParameterError: ``name`` is not one of :data:`EXAMPLE_DRIVES`.
    """
    choice("name", name, EXAMPLE_DRIVES)
    folder = importlib.resources.files("orthoglide_pin.drives") / "examples"
    return folder / EXAMPLE_DRIVES[name]


def example_drive_text(name: str = DEFAULT_EXAMPLE) -> str:
    """The text of the shipped example drive file ``name`` (YAML, with comments)."""
    return example_drive_file(name).read_text(encoding="utf-8")
