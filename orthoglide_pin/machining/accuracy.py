"""Part accuracy along a planned program: forces, surface error and the error budget.

:func:`accuracy_along_plan` samples the plan every ``dt``
(:func:`~orthoglide_pin.machining.plan_samples.cut_samples`), and at each
sample that cuts:

* the feed per tooth ``f_t = v / (N n)`` from the **planned** path speed's part
  in the feed plane (not the programmed feed), ``n`` the spindle speed [rev/s];
* the milling force over one revolution in the feed frame
  (:func:`~orthoglide_pin.machining.forces.milling_forces`), its mean and
  peak, and the mean in the world frame;
* the deflection and the surface error, static and peak
  (:mod:`~orthoglide_pin.machining.surface_error`), with the machine's
  compliance at the point and the tool's own;
* the error budget (:func:`~orthoglide_pin.machining.budget.error_budget`)
  at the cutting samples: compliance (the static deflection), and when given
  the calibration's geometric term, the servo's contour error and a
  temperature rise.

Samples that do not cut carry zeros. The result gives per-sample arrays
(:meth:`AccuracyResult.columns`), the maxima per program line
(:attr:`AccuracyResult.blocks`) and a strict-JSON summary
(:meth:`AccuracyResult.summary`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._io import strict_json
from orthoglide_pin._validation import finite_rows, float_array, instance_of
from orthoglide_pin.exceptions import CutConditionsError, InvalidParameterError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.digest import check_design
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.machining._checks import RPM_PER_RAD_S, number
from orthoglide_pin.machining.budget import ErrorBudget, error_budget
from orthoglide_pin.machining.cutting import CutConditions
from orthoglide_pin.machining.forces import milling_forces
from orthoglide_pin.machining.plan_samples import CutSamples, cut_samples
from orthoglide_pin.machining.surface_error import (
    feed_frames,
    machine_compliance,
    surface_errors,
    tool_compliance,
    wall_sides,
)
from orthoglide_pin.planning.plan import Plan

if TYPE_CHECKING:
    from orthoglide_pin.calibration.result import Calibration

FloatArray = NDArray[np.float64]

#: Sampling step when none is given [s], while it gives at most :data:`AUTO_SAMPLES`.
DEFAULT_DT: Final[float] = 0.005
AUTO_SAMPLES: Final[int] = 50_000
#: Cutting samples per batch of forces and compliances (bounds the memory).
BATCH: Final[int] = 4096


@dataclass(frozen=True)
class BlockAccuracy:
    """The largest values over the cutting samples of one program line.

    Attributes:
        line: The program line.
        samples: Its cutting samples.
        force_mean: Largest magnitude of the revolution's mean force [N].
        force_peak: Largest force magnitude over a revolution [N].
        surface_static: Static surface error of largest magnitude [m] (signed).
        surface_peak: Surface error of largest magnitude over a revolution [m] (signed).
        feed_peak: Error along the feed of largest magnitude over a revolution [m] (signed).
        surface_generated: Surface error as the wall is generated, of largest
            magnitude [m] (signed).
    """

    line: int
    samples: int
    force_mean: float
    force_peak: float
    surface_static: float
    surface_peak: float
    feed_peak: float
    surface_generated: float


@dataclass(frozen=True)
class AccuracyResult:
    """Part accuracy along a plan (see the module); arrays per sample, (n,) or (n, 3).

    Attributes:
        samples: The plan sampled (times, points, lines, cutting flags).
        spindle_speed: Spindle speed [rad/s].
        feed_per_tooth: f_t [m].
        force_mean: Mean force on the tool over a revolution [N], (n, 3), world frame.
        force_peak: Largest force magnitude over a revolution [N].
        deflection: Static deflection [m], (n, 3), world frame.
        surface_static: Surface error under the mean force [m] (positive: material left).
        surface_peak: Surface error of largest magnitude over a revolution [m].
        feed_static: Error along the feed under the mean force [m].
        feed_peak: Error along the feed of largest magnitude over a revolution [m].
        surface_generated: Surface error as the edge generates the wall, of
            largest magnitude over the cut's height [m] (positive: material left).
        blocks: The maxima per program line, in order.
        budget: The error budget at the cutting samples.
        cut: The cutting conditions.
    """

    samples: CutSamples
    spindle_speed: float
    feed_per_tooth: FloatArray
    force_mean: FloatArray
    force_peak: FloatArray
    deflection: FloatArray
    surface_static: FloatArray
    surface_peak: FloatArray
    feed_static: FloatArray
    feed_peak: FloatArray
    surface_generated: FloatArray
    blocks: tuple[BlockAccuracy, ...]
    budget: ErrorBudget
    cut: CutConditions

    def columns(self) -> dict[str, FloatArray]:
        """Per-sample columns (SI units), for a CSV file: name -> (n,) values."""
        s = self.samples
        out = {"t": s.t, "x": s.points[:, 0], "y": s.points[:, 1], "z": s.points[:, 2]}
        out["line"] = s.line.astype(np.float64)
        out["cutting"] = s.cutting.astype(np.float64)
        out["feed_per_tooth"] = self.feed_per_tooth
        for i, axis in enumerate("xyz"):
            out[f"force_mean_{axis}"] = self.force_mean[:, i]
        out["force_peak"] = self.force_peak
        for i, axis in enumerate("xyz"):
            out[f"deflection_{axis}"] = self.deflection[:, i]
        out["surface_error_static"] = self.surface_static
        out["surface_error_peak"] = self.surface_peak
        out["feed_error_static"] = self.feed_static
        out["feed_error_peak"] = self.feed_peak
        out["surface_error_generated"] = self.surface_generated
        return out

    def summary(self) -> dict[str, Any]:
        """The figures of the run, strict JSON (SI units; the spindle speed also in rpm).

        Keys: ``spindle_speed`` [rad/s], ``spindle_speed_rpm``, ``material``
        (``name``, ``source``), ``samples``, ``cutting_samples``,
        ``feed_per_tooth_max`` [m], ``force_mean_max`` and ``force_peak_max``
        [N], ``surface_error_static_max``, ``surface_error_peak_max`` and
        ``feed_error_peak_max`` and ``surface_error_generated_max`` [m] (the
        values of largest magnitude, signed),
        ``worst`` (``t`` [s], ``point`` [m], ``line`` of the largest peak
        surface error, or ``None`` when nothing cuts), ``blocks`` (the fields
        of :class:`BlockAccuracy` per line) and ``budget``
        (:meth:`~orthoglide_pin.machining.budget.ErrorBudget.summary`).
        """
        cutting = self.samples.cutting
        worst = int(np.argmax(np.abs(self.surface_peak))) if cutting.any() else None
        m = self.cut.material
        data = {
            "spindle_speed": self.spindle_speed,
            "spindle_speed_rpm": self.spindle_speed * RPM_PER_RAD_S,
            "material": {"name": m.name, "source": m.source},
            "samples": int(self.samples.t.size),
            "cutting_samples": int(cutting.sum()),
            "feed_per_tooth_max": float(self.feed_per_tooth.max(initial=0.0)),
            "force_mean_max": float(np.linalg.norm(self.force_mean, axis=1).max(initial=0.0)),
            "force_peak_max": float(self.force_peak.max(initial=0.0)),
            "surface_error_static_max": _signed_max(self.surface_static),
            "surface_error_peak_max": _signed_max(self.surface_peak),
            "feed_error_peak_max": _signed_max(self.feed_peak),
            "surface_error_generated_max": _signed_max(self.surface_generated),
            "worst": None
            if worst is None
            else {
                "t": float(self.samples.t[worst]),
                "point": self.samples.points[worst],
                "line": int(self.samples.line[worst]),
            },
            "blocks": [vars(b) for b in self.blocks],
            "budget": self.budget.summary(),
        }
        return dict(strict_json(data))


def _signed_max(values: FloatArray) -> float:
    """The value of largest magnitude (0 for none)."""
    return float(values[int(np.argmax(np.abs(values)))]) if values.size else 0.0


def _servo_at(servo: tuple[ArrayLike, ArrayLike], t: FloatArray) -> FloatArray:
    if not isinstance(servo, (tuple, list)) or len(servo) != 2:
        raise InvalidParameterError("servo", servo, "(times [s], contour errors [m]) arrays")
    times, errors = float_array(servo[0]), float_array(servo[1])
    ok = times.ndim == 1 and times.size >= 1 and errors.shape == times.shape
    if not ok or not (np.isfinite(times).all() and np.isfinite(errors).all()):
        raise InvalidParameterError("servo", servo, "(times [s], contour errors [m]), equal sizes")
    if (np.diff(times) < 0.0).any():
        raise InvalidParameterError("servo", servo, "times in increasing order")
    return np.asarray(np.interp(t, times, errors), dtype=np.float64)


def _blocks(result: dict[str, FloatArray], line: NDArray[np.intp]) -> tuple[BlockAccuracy, ...]:
    out = []
    for ln in np.unique(line):
        sel = line == ln
        out.append(
            BlockAccuracy(
                int(ln),
                int(sel.sum()),
                float(result["force_mean"][sel].max()),
                float(result["force_peak"][sel].max()),
                _signed_max(result["surface_static"][sel]),
                _signed_max(result["surface_peak"][sel]),
                _signed_max(result["feed_peak"][sel]),
                _signed_max(result["surface_generated"][sel]),
            )
        )
    return tuple(out)


def accuracy_along_plan(
    plan: Plan,
    cut: CutConditions,
    params: OrthoglideParams | None = None,
    *,
    dt: float | None = None,
    spindle_speed: float | None = None,
    calibration: Calibration | None = None,
    servo: tuple[ArrayLike, ArrayLike] | None = None,
    temperature_rise: float | None = None,
) -> AccuracyResult:
    """Cutting forces, surface error and the error budget along a plan (see the module).

    Args:
        plan: The plan (:func:`~orthoglide_pin.planning.plan.plan_program`).
        cut: The cutting conditions (:func:`~orthoglide_pin.machining.cutting.read_cut_file`).
        params: The machine the plan was made for (the prototype when ``None``).
        dt: Sampling step [s]; :data:`DEFAULT_DT` when ``None`` (coarser on a
            long plan, to at most :data:`AUTO_SAMPLES` samples).
        spindle_speed: Spindle speed [rad/s] (the program's ``S``); it replaces
            the cut file's; needed when the cut file says ``program``.
        calibration: A calibration of this machine for the budget's geometric term.
        servo: ``(times [s], contour errors [m])`` of a simulated run, for the
            budget's servo term (interpolated at the samples).
        temperature_rise: Uniform temperature rise [K] for the thermal term.

    Raises:
        CutConditionsError: No spindle speed (neither given nor in the cut file).
        InvalidParameterError: A bad argument.
        DesignMismatchError: The plan or the calibration was made for another design.
        UnreachablePointError, SingularConfigurationError: A cutting point where
            the stiffness model gives no stiffness.
    """
    plan = instance_of("plan", plan, Plan, "a Plan (plan_program)")
    cut = instance_of("cut", cut, CutConditions, "CutConditions (read_cut_file)")
    machine = as_params(params)
    if plan.design is not None:
        check_design(plan.design, machine, "the plan", redo="plan it again")
    omega = cut.spindle_speed if spindle_speed is None else spindle_speed
    if omega is None:
        raise CutConditionsError(
            "spindle_speed", None, "a spindle speed: the cut file's, or the program's S given"
        )
    omega = number("spindle_speed", omega, "spindle_speed_rad")
    if dt is None:
        dt = max(DEFAULT_DT, plan.cycle_time / (AUTO_SAMPLES - 2))
    s = cut_samples(plan, cut, dt)
    n, tool = s.t.size, cut.tool
    rev_per_s = omega / (2.0 * math.pi)
    idx = np.flatnonzero(s.cutting)
    plane = np.linalg.norm(s.plane_tangent, axis=1)
    ft = np.zeros(n)
    ft[idx] = s.speed[idx] * plane[idx] / (tool.teeth * rev_per_s)
    depth, imm = np.zeros(n), np.zeros((n, 2))
    milling = np.full(n, "down", dtype=object)
    for ln in np.unique(s.line[idx]):
        e = cut.engagement_at(int(ln))
        assert e is not None  # cutting samples have an engagement
        sel = idx[s.line[idx] == ln]
        depth[sel], imm[sel], milling[sel] = e.axial_depth, e.immersion(tool.diameter), e.milling
    out = {k: np.zeros(n) for k in ("force_peak", "surface_static", "surface_peak")}
    out |= {k: np.zeros(n) for k in ("feed_static", "feed_peak", "surface_generated")}
    f_world, deflection = np.zeros((n, 3)), np.zeros((n, 3))
    extra = tool_compliance(tool, plan.path.program.axes)
    for lo in range(0, idx.size, BATCH):
        sel = idx[lo : lo + BATCH]
        forces = milling_forces(
            ft[sel], depth[sel], imm[sel], tool, cut.material, keep_period=True,
            milling=milling[sel],
        )  # fmt: skip
        frames = feed_frames(s.tangent[sel], s.tool_axis)
        c = machine_compliance(s.points[sel], machine, extra)
        assert forces.over_period is not None
        err = surface_errors(
            c, frames, wall_sides(milling[sel]), forces.mean, forces.over_period, forces.at_wall
        )
        f_world[sel] = np.einsum("nij,nj->ni", frames, forces.mean)
        deflection[sel] = err.deflection
        out["force_peak"][sel] = forces.peak
        out["surface_static"][sel], out["surface_peak"][sel] = err.surface_static, err.surface_peak
        out["feed_static"][sel], out["feed_peak"][sel] = err.feed_static, err.feed_peak
        out["surface_generated"][sel] = err.surface_generated
    mean_size = np.linalg.norm(f_world, axis=1)
    servo_terms = None if servo is None else _servo_at(servo, s.t[idx])
    normals = None
    if servo_terms is not None:
        frames = feed_frames(s.tangent[idx], s.tool_axis)
        normals = -frames[:, :, 1] * wall_sides(milling[idx])[:, None]
    if idx.size:
        budget = error_budget(
            finite_rows("points", s.points[idx], 3), machine, compliance=deflection[idx],
            servo=servo_terms, normals=normals, calibration=calibration,
            temperature_rise=temperature_rise,
        )  # fmt: skip
    else:  # nothing cuts: no point of the part
        budget = ErrorBudget(np.zeros((0, 3)), {}, np.zeros(0), np.zeros(0), ())
    return AccuracyResult(
        s, omega, ft, f_world, out["force_peak"], deflection, out["surface_static"],
        out["surface_peak"], out["feed_static"], out["feed_peak"], out["surface_generated"],
        _blocks(
            {k: v[idx] for k, v in out.items()} | {"force_mean": mean_size[idx]}, s.line[idx]
        ), budget, cut,
    )  # fmt: skip
