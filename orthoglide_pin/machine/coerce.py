"""The machine an entry point is given: its parameters, a model built from them, or none.

One rule for the whole API. A function or class that needs the machine takes
its :class:`~orthoglide_pin.machine.params.OrthoglideParams`, and ``None``
means the prototype (:func:`~orthoglide_pin.machine.params.prototype`). One
that works on the Pinocchio model takes the parameters too, and also a model
already built (:class:`~orthoglide_pin.machine.closed_loop.ClosedLoopModel`),
so that a caller with many calls to make builds it once; the dynamics also
take their own :class:`~orthoglide_pin.dynamics.inverse.ClosedLoopDynamics`
(:func:`orthoglide_pin.dynamics.motion_forms.as_dynamics`). Anything else is
refused with one line naming the argument.

:func:`~orthoglide_pin.machine.closed_loop.as_model` builds or recognises the
model; it lives with the model, which imports Pinocchio. This module does not
import it, so that the closed-form layers can use :func:`as_params` and
:func:`is_model` and stay light.
"""

from __future__ import annotations

import sys
from typing import Any

from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.params import OrthoglideParams, prototype

#: What :func:`as_params` accepts, for the error message.
PARAMS_ALLOWED = "OrthoglideParams, or None for the prototype"
#: What :func:`~orthoglide_pin.machine.closed_loop.as_model` accepts (error messages).
MODEL_ALLOWED = "a ClosedLoopModel, OrthoglideParams, or None for the prototype"
#: What an ``urdf`` argument (the text given instead of rendering) must be.
URDF_TEXT = "a URDF document (str), or None to render params"


def _refuse(name: str, value: Any, allowed: str) -> InvalidParameterError:
    return InvalidParameterError(name, value, f"{allowed}, not {type(value).__name__}")


def as_params(value: Any, name: str = "params") -> OrthoglideParams:
    """The machine's parameters: ``value`` itself, or the prototype's for ``None``.

    Args:
        value: ``OrthoglideParams`` or ``None``.
        name: The argument's name, for the error message.

    Raises:
        InvalidParameterError: Naming ``name`` and the type received.
    """
    if value is None:
        return prototype()
    if not isinstance(value, OrthoglideParams):
        raise _refuse(name, value, PARAMS_ALLOWED)
    return value


def is_model(value: Any) -> bool:
    """Whether ``value`` is a ``ClosedLoopModel`` (without importing Pinocchio to tell)."""
    module = sys.modules.get("orthoglide_pin.machine.closed_loop")
    return module is not None and isinstance(value, module.ClosedLoopModel)


__all__ = ["MODEL_ALLOWED", "PARAMS_ALLOWED", "URDF_TEXT", "as_params", "is_model"]
