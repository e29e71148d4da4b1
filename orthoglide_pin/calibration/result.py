"""A calibration as a file: the identified geometry, its uncertainty, its data.

``calibration.yaml`` (written by ``orthoglide calibrate``) holds::

    format: orthoglide-calibration
    version: 1
    leg_length: 0.31            # nominal L [m]: the drawing the fit started from
    design: "bf09cda97f8d037e"  # the design digest of the machine (og.design_digest)
    parameters: {a1_x: ..., alpha1: ..., L1: ..., ...}   # identified [m, rad]
    std: {a1_x: ..., ...}       # standard deviations [m, rad]
    nominal: {a1_x: ..., ...}   # the drawing's values
    noise_estimate: ...         # measurement noise per axis [m]
    rms_before: ...             # RMS tool error of the drawing [m]
    rms_after: ...              # RMS tool error after calibration [m]
    outliers: [...]             # 0-based rows left out of the fit
    unidentifiable: [...]       # combinations held at their nominal values
    measurements: {rows: N, sha256: ...}

Floats are written at full precision (``repr``), so a loaded calibration
predicts exactly what the fit did. :func:`load_calibration` checks every
field and returns a :class:`Calibration`, whose kinematics compensate the
machine: ``inverse_kinematics(p)`` gives the slider values that put the real
tool at ``p``. A calibration belongs to one design (``design``, its digest):
:meth:`Calibration.check_design` refuses another, as every command and
function that applies it to a machine does; a file without ``design`` (written
before designs were recorded) is refused there too, naming the line to add.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import atomic_write_text, read_yaml_mapping
from orthoglide_pin._validation import instance_of, path_argument
from orthoglide_pin.calibration.identification import Identification
from orthoglide_pin.calibration.measurements import Measurements, check_measured_design
from orthoglide_pin.calibration.model import PARAMETER_NAMES, GeometricModel
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.digest import (
    DIGEST_QUANTUM,
    check_design,
    checked_digest,
    design_digest,
)
from orthoglide_pin.machine.legs import LegGeometry
from orthoglide_pin.machine.params import OrthoglideParams

FloatArray = NDArray[np.float64]

#: The ``format`` field of a calibration file.
FORMAT: Final[str] = "orthoglide-calibration"
#: The version of the format this package writes and reads.
VERSION: Final[int] = 1


@dataclass(frozen=True)
class Calibration:
    """An identified machine, ready to compensate its kinematics.

    Attributes:
        model: The identified geometry.
        nominal: The drawing the identification started from.
        std: Standard deviation of each parameter [m or rad], shape (18,).
        noise_estimate: Measurement noise per axis [m].
        rms_before: RMS tool position error of the drawing over the poses [m].
        rms_after: RMS tool position error after calibration [m].
        outliers: 0-based rows of the measurements left out of the fit.
        unidentifiable: Combinations held at their nominal values.
        poses: Number of rows of the measurements.
        measurements_sha256: Hash of the measurement file.
        design: The design digest of the machine it was made for
            (:func:`~orthoglide_pin.machine.digest.design_digest`), or ``None``
            when unknown (a file written before designs were recorded): then
            :meth:`check_design` refuses every design.
    """

    model: GeometricModel
    nominal: GeometricModel
    std: FloatArray
    noise_estimate: float
    rms_before: float
    rms_after: float
    outliers: tuple[int, ...]
    unidentifiable: tuple[dict[str, float], ...]
    poses: int
    measurements_sha256: str
    design: str | None = None

    @classmethod
    def from_identification(
        cls,
        result: Identification,
        data: Measurements,
        params: OrthoglideParams | None = None,
    ) -> Calibration:
        """The calibration of an identification from a measurement file.

        Args:
            result: The identification
                (:func:`~orthoglide_pin.calibration.identification.identify`).
            data: The measurements it was made from.
            params: The design whose drawing the identification started from
                (recorded as its digest); the prototype when ``None``.

        Raises:
            DesignMismatchError: The identification started from another leg
                length than the design's, or the measurements record another
                design (their first line).
        """
        result = instance_of("result", result, Identification, "an Identification (og.identify)")
        data = instance_of("data", data, Measurements, "Measurements (og.read_measurements)")
        digest = design_digest(params)
        legs = float(result.nominal.mean_length)
        if abs(legs - as_params(params).leg_length) > DIGEST_QUANTUM:  # started from another
            check_design(None, params, "the identification", leg_length=legs)
        check_measured_design(data, params)
        return cls(
            model=result.model,
            nominal=result.nominal,
            std=result.std,
            noise_estimate=result.noise_estimate,
            rms_before=result.rms_before,
            rms_after=result.rms_after,
            outliers=result.outliers,
            unidentifiable=result.unidentifiable,
            poses=len(data),
            measurements_sha256=data.sha256,
            design=digest,
        )

    def check_design(self, params: OrthoglideParams | None, what: str = "the calibration") -> None:
        """Refuse to apply this calibration to another design than its own.

        Args:
            params: The design it is applied to; the prototype when ``None``.
            what: The calibration as the user knows it (its file), for the message.

        Raises:
            DesignMismatchError: Its design digest is another, or it records none
                (one line naming both designs, and their leg lengths when they differ).
        """
        check_design(
            self.design,
            params,
            what,
            leg_length=float(self.nominal.mean_length),
            redo="run orthoglide calibrate again with this design",
        )

    def direct_kinematics(self, q: ArrayLike) -> FloatArray:
        """Where the real tool is for slider values [m], (N, 3) -> (N, 3)."""
        return self.model.direct_kinematics(q)

    def inverse_kinematics(self, points: ArrayLike) -> FloatArray:
        """Slider values [m] that put the real tool at ``points`` [m], (N, 3) -> (N, 3)."""
        return self.model.inverse_kinematics(points)

    def legs(self, params: OrthoglideParams | None = None) -> LegGeometry:
        """The built machine's legs for the description of its design.

        ``og.ClosedLoopModel(params, urdf=og.render_urdf(params, legs=cal.legs(params)))``
        is the closed-loop Pinocchio model of the calibrated machine.

        Args:
            params: The design the legs are drawn on (the prototype when
                ``None``): the calibration's own (:meth:`check_design`).

        Raises:
            DesignMismatchError: The calibration was made for another design.
        """
        self.check_design(params)
        return self.model.legs(self.nominal.mean_length)

    def parameters(self) -> dict[str, dict[str, float]]:
        """Per parameter: ``value``, ``nominal``, ``error`` and ``std`` [m or rad]."""
        value, nominal = self.model.vector(), self.nominal.vector()
        return {
            name: {
                "value": float(value[k]),
                "nominal": float(nominal[k]),
                "error": float(value[k] - nominal[k]),
                "std": float(self.std[k]),
            }
            for k, name in enumerate(PARAMETER_NAMES)
        }

    def to_dict(self) -> dict[str, Any]:
        """The content of ``calibration.yaml`` (plain Python values)."""
        return {
            "format": FORMAT,
            "version": VERSION,
            "leg_length": float(self.nominal.mean_length),
            **({} if self.design is None else {"design": self.design}),
            "parameters": _named(self.model.vector()),
            "std": _named(self.std),
            "nominal": _named(self.nominal.vector()),
            "noise_estimate": float(self.noise_estimate),
            "rms_before": float(self.rms_before),
            "rms_after": float(self.rms_after),
            "outliers": list(self.outliers),
            "unidentifiable": [dict(c) for c in self.unidentifiable],
            "measurements": {"rows": self.poses, "sha256": self.measurements_sha256},
        }


def _named(values: FloatArray) -> dict[str, float]:
    return {name: float(v) for name, v in zip(PARAMETER_NAMES, values, strict=True)}


def write_calibration(path: str | os.PathLike[str], calibration: Calibration) -> None:
    """Write ``calibration.yaml`` atomically (see the module for its fields)."""
    path = path_argument("path", path)
    instance_of("calibration", calibration, Calibration, "a Calibration (load_calibration)")
    data = calibration.to_dict()
    if "design" in data:
        data["design"] = _Quoted(data["design"])
    text = yaml.dump(data, Dumper=_Dumper, sort_keys=False, width=100)
    atomic_write_text(path, f"# orthoglide calibration (SI units: m, rad)\n{text}")


class _Dumper(yaml.SafeDumper):
    """``safe_dump`` that quotes the design digest: ``1234e567...`` is a number in YAML 1.2."""


class _Quoted(str):
    """A string always written in double quotes."""


_Dumper.add_representer(
    _Quoted, lambda d, v: d.represent_scalar("tag:yaml.org,2002:str", str(v), style='"')
)


def _number(where: str, value: Any, *, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InvalidParameterError(where, value, "a number")
    v = float(value)
    if not math.isfinite(v) or (positive and v <= 0.0) or (not positive and v < 0.0):
        raise InvalidParameterError(where, value, "a finite number >= 0" if not positive else
                                    "a positive finite number")  # fmt: skip
    return v


def _vector(data: dict[str, Any], key: str, *, signed: bool) -> FloatArray:
    block = data.get(key)
    if not isinstance(block, dict):
        raise InvalidParameterError(
            key, block, f"a mapping of the 18 parameters ({PARAMETER_NAMES[0]}, ...)"
        )
    extra = sorted(set(block) - set(PARAMETER_NAMES))
    missing = [n for n in PARAMETER_NAMES if n not in block]
    if extra or missing:
        what = f"unknown {extra[0]}" if extra else f"missing {missing[0]}"
        raise InvalidParameterError(
            key, what, f"exactly the parameters {', '.join(PARAMETER_NAMES)}"
        )
    out = np.empty(len(PARAMETER_NAMES))
    for k, name in enumerate(PARAMETER_NAMES):
        value = block[name]
        if signed:
            if (
                isinstance(value, bool)
                or not isinstance(value, (int, float))
                or not math.isfinite(value)
            ):
                raise InvalidParameterError(f"{key}.{name}", value, "a finite number")
            out[k] = float(value)
        else:
            out[k] = _number(f"{key}.{name}", value)
    return out


def load_calibration(path: str | os.PathLike[str]) -> Calibration:
    """Read a ``calibration.yaml`` written by ``orthoglide calibrate``.

    Args:
        path: The file.

    Returns:
        The calibration, whose ``direct_kinematics(q)`` and
        ``inverse_kinematics(p)`` take and return (N, 3) arrays [m].

    The design it was made for (``design``) is read, not checked: a machine
    checks it when the calibration is applied to it (:meth:`Calibration.check_design`).

    Raises:
        InvalidParameterError: Unreadable file, another format or version, a
            missing, unknown or non-finite field, a malformed ``design``.
    """
    data = read_yaml_mapping(path, "calibration file")
    if data.get("format") != FORMAT:
        raise InvalidParameterError(
            "format", data.get("format"), f"{FORMAT!r}: a file of orthoglide calibrate"
        )
    if data.get("version") != VERSION:
        raise InvalidParameterError("version", data.get("version"), f"{VERSION}")
    theta = _vector(data, "parameters", signed=True)
    nominal = _vector(data, "nominal", signed=True)
    std = _vector(data, "std", signed=False)
    outliers = data.get("outliers", [])
    if not isinstance(outliers, list) or not all(
        isinstance(i, int) and not isinstance(i, bool) and i >= 0 for i in outliers
    ):
        raise InvalidParameterError("outliers", outliers, "a list of row numbers (0-based)")
    unident = data.get("unidentifiable", [])
    if not isinstance(unident, list) or not all(
        isinstance(c, dict)
        and all(k in PARAMETER_NAMES and isinstance(v, (int, float)) for k, v in c.items())
        for c in unident
    ):
        raise InvalidParameterError(
            "unidentifiable", unident, "a list of mappings of parameter names to coefficients"
        )
    meas = data.get("measurements")
    if (
        not isinstance(meas, dict)
        or not isinstance(meas.get("rows"), int)
        or not isinstance(meas.get("sha256"), str)
    ):
        raise InvalidParameterError(
            "measurements", meas, "a mapping with rows (an integer) and sha256 (text)"
        )
    design = data.get("design")
    return Calibration(
        model=GeometricModel.from_vector(theta),
        nominal=GeometricModel.from_vector(nominal),
        std=std,
        noise_estimate=_number("noise_estimate", data.get("noise_estimate")),
        rms_before=_number("rms_before", data.get("rms_before")),
        rms_after=_number("rms_after", data.get("rms_after")),
        outliers=tuple(outliers),
        unidentifiable=tuple({k: float(v) for k, v in c.items()} for c in unident),
        poses=meas["rows"],
        measurements_sha256=meas["sha256"],
        design=None if design is None else checked_digest("design", design),
    )
