"""The machine in a physics engine (MuJoCo, ``pip install 'orthoglide-pin[sim]'``).

* :mod:`~orthoglide_pin.simulation.mjcf`: the machine as MJCF, with its loop
  closures as equality constraints, its drives and its force limits.

The module imports Pinocchio (through the dynamics layer): its names are loaded
on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports

if TYPE_CHECKING:
    from orthoglide_pin.simulation.mjcf import (
        mjcf_text,
        slider_force_limit,
        slider_ratio,
        write_mjcf,
    )

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        name: "orthoglide_pin.simulation.mjcf"
        for name in ("mjcf_text", "slider_force_limit", "slider_ratio", "write_mjcf")
    },
    globals(),
)

__all__ = ["mjcf_text", "slider_force_limit", "slider_ratio", "write_mjcf"]
