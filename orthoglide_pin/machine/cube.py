"""The prescribed workspace of a machine: an axis-aligned cube.

The Orthoglide is designed for a cube (paper, section 3.4): the tool must reach
every point of it with the velocity transmission factors within their bounds.
The cube is given by its lowest corner ``Q1`` (the corner on the slider side,
where the sliders are the most retracted) and its side ``Lw``; the opposite
corner is ``Q2 = Q1 + Lw (1, 1, 1)``. Every command and function that works "on
the workspace" (worst-case maps, sweeps in fixed-cube mode, the standard
cycle, the viewer) reads the cube from the machine's parameters
(:attr:`~orthoglide_pin.machine.params.OrthoglideParams.workspace`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Cube:
    """An axis-aligned cube ``[corner, corner + side]`` in the world frame.

    Attributes:
        corner: Lowest corner ``Q1`` [m], three numbers.
        side: Side ``Lw`` [m].
    """

    corner: tuple[float, float, float]
    side: float

    @property
    def q1(self) -> FloatArray:
        """Lowest corner ``Q1`` [m], shape (3,) (a fresh array)."""
        return np.array(self.corner, dtype=np.float64)

    @property
    def q2(self) -> FloatArray:
        """Highest corner ``Q2 = Q1 + side (1, 1, 1)`` [m], shape (3,)."""
        return self.q1 + self.side

    @property
    def center(self) -> FloatArray:
        """Centre of the cube [m], shape (3,)."""
        return self.q1 + 0.5 * self.side

    def describe(self) -> str:
        """The cube in words, in mm: ``"200 mm cube, lowest corner Q1 (x, y, z) mm"``."""
        corner = ", ".join(f"{1e3 * c + 0.0:.2f}" for c in self.corner)
        return f"{1e3 * self.side:.6g} mm cube, lowest corner Q1 ({corner}) mm"

    def to_dict(self) -> dict[str, object]:
        """JSON-ready ``{"corner": [x, y, z], "side": Lw}`` [m]."""
        return {"corner": list(self.corner), "side": self.side}
