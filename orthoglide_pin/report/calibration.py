"""The outputs of a calibration: ``calibration.yaml``, its page and the residuals.

:func:`write_calibration_outputs` writes, into one directory, atomically
(:func:`~orthoglide_pin._outdir.atomic_directory`, the same rules as the
report's directory):

* ``calibration.yaml``: the identified parameters, their standard deviations,
  the noise estimate and the hash of the measurements
  (:mod:`orthoglide_pin.calibration.result`);
* ``calibration.html``: one self-contained page: the residuals before and
  after per axis, the parameters with their 95 % confidence intervals, the
  poses in the cube, the outliers and what could not be determined;
* ``residuals.csv``: one row per pose, SI units: ``row, q1, q2, q3, x, y, z``
  (the measurement), ``outlier`` (0 or 1), ``before_x, before_y, before_z``
  (drawing minus measurement [m]) and ``after_x, after_y, after_z``
  (identified model minus measurement [m]).

The page shows lengths in mm and µm and angles in µrad; the files keep SI.
"""

from __future__ import annotations

import io
import os
from pathlib import Path
from typing import Any, Final

import numpy as np

from orthoglide_pin._outdir import atomic_directory
from orthoglide_pin.calibration.identification import Identification
from orthoglide_pin.calibration.measurements import Measurements
from orthoglide_pin.calibration.model import PARAMETER_NAMES, PARAMETER_UNITS
from orthoglide_pin.calibration.result import Calibration, write_calibration
from orthoglide_pin.report.page import escape, figure, image, page, png, table

#: File names inside the calibration directory.
YAML_NAME: Final = "calibration.yaml"
HTML_NAME: Final = "calibration.html"
CSV_NAME: Final = "residuals.csv"
#: Columns of ``residuals.csv``.
CSV_COLUMNS: Final = (
    "row",
    "q1",
    "q2",
    "q3",
    "x",
    "y",
    "z",
    "outlier",
    "before_x",
    "before_y",
    "before_z",
    "after_x",
    "after_y",
    "after_z",
)
#: Half-width of the confidence intervals shown, in standard deviations (95 %).
CI_SIGMAS: Final = 1.96
_UM: Final = 1e6
_AXES: Final = ("x", "y", "z")


def residuals_csv(result: Identification, data: Measurements) -> str:
    """The content of ``residuals.csv`` (see the module)."""
    out = io.StringIO()
    out.write(",".join(CSV_COLUMNS) + "\n")
    outliers = set(result.outliers)
    for r in range(len(data)):
        measured = (*data.q[r], *data.points[r])
        residuals = (*result.residuals_before[r], *result.residuals_after[r])
        cells = [str(r), *(repr(float(v)) for v in measured), "1" if r in outliers else "0"]
        cells += [repr(float(v)) for v in residuals]
        out.write(",".join(cells) + "\n")
    return out.getvalue()


def _residual_figure(result: Identification) -> bytes:
    fig = figure(9.0, 5.5)
    axes = fig.subplots(2, 3, sharex=True)
    rows = np.arange(len(result.residuals_before))
    inl = result.inliers
    for k, name in enumerate(_AXES):
        for line, (label, res) in enumerate(
            (("drawing", result.residuals_before), ("calibrated", result.residuals_after))
        ):
            ax = axes[line, k]
            ax.plot(rows[inl], _UM * res[inl, k], ".", ms=4, color="tab:blue", label="pose")
            if (~inl).any():
                ax.plot(rows[~inl], _UM * res[~inl, k], "x", color="tab:red", label="outlier")
            ax.axhline(0.0, color="0.5", lw=0.8)
            ax.set_title(f"{label}: error along {name}", fontsize=9)
            ax.set_ylabel("tool position error [µm]")
            if line == 1:
                ax.set_xlabel("pose (row of the measurements)")
                lim = 4.0 * _UM * max(result.noise_estimate, 1e-9)
                ax.set_ylim(-lim, lim)  # outliers beyond are left off this scale
    axes[0, 0].legend(fontsize=8)
    return png(fig)


def _parameter_figure(result: Identification) -> bytes:
    fig = figure(9.0, 3.6)
    err = result.model.vector() - result.nominal.vector()
    ci = CI_SIGMAS * result.std
    lengths = [k for k, u in enumerate(PARAMETER_UNITS) if u == "m"]
    angles = [k for k, u in enumerate(PARAMETER_UNITS) if u == "rad"]
    for ax, idx, unit in zip(fig.subplots(1, 2), (lengths, angles), ("µm", "µrad"), strict=True):
        x = np.arange(len(idx))
        ax.errorbar(x, _UM * err[idx], yerr=_UM * ci[idx], fmt="o", ms=4, capsize=3)
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xticks(x, [PARAMETER_NAMES[k] for k in idx], rotation=60, fontsize=8)
        ax.set_ylabel(f"error from the drawing [{unit}]")
        ax.set_title("identified error, 95 % interval", fontsize=9)
    return png(fig)


def _pose_figure(result: Identification, data: Measurements) -> bytes:
    fig = figure(5.0, 4.5)
    ax = fig.add_subplot(projection="3d")
    p = 1e3 * data.points
    inl = result.inliers
    ax.scatter(p[inl, 0], p[inl, 1], p[inl, 2], s=10, color="tab:blue", label="pose")
    if (~inl).any():
        ax.scatter(p[~inl, 0], p[~inl, 1], p[~inl, 2], s=30, marker="x", color="tab:red",
                   label="outlier")  # fmt: skip
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.legend(fontsize=8)
    return png(fig)


def outliers_text(outliers: tuple[int, ...], poses: int) -> str:
    """The poses left out of the fit, counted, then their rows.

    ``"2 of 60 poses: rows 3, 41 (column row of residuals.csv, from 0)"``, or
    ``"none of 60 poses"``: the count first, so a row number never reads as one.
    """
    if not outliers:
        return f"none of {poses} poses"
    rows = ", ".join(map(str, outliers))
    word = "row" if len(outliers) == 1 else "rows"
    return f"{len(outliers)} of {poses} poses: {word} {rows} ({CSV_NAME}'s row column, from 0)"


def _value(k: int, value: float) -> str:
    return f"{_UM * value:+.2f} " + ("µm" if PARAMETER_UNITS[k] == "m" else "µrad")


def calibration_html(calibration: Calibration, result: Identification, data: Measurements) -> str:
    """The self-contained page of a calibration (see the module)."""
    images = {
        "residuals": _residual_figure(result),
        "parameters": _parameter_figure(result),
        "poses": _pose_figure(result, data),
    }
    summary = table(
        ["quantity", "value"],
        [
            ["poses (rows)", len(data)],
            ["outliers left out of the fit", outliers_text(result.outliers, len(data))],
            ["RMS tool error, drawing", f"{_UM * calibration.rms_before:.2f} µm"],
            ["RMS tool error, calibrated", f"{_UM * calibration.rms_after:.2f} µm"],
            ["noise estimate (per axis)", f"{_UM * calibration.noise_estimate:.2f} µm"],
            ["measurements (SHA-256)", data.sha256[:16] + "…"],
            ["design (digest)", calibration.design or "not recorded"],
        ],
    )
    params = table(
        ["parameter", "drawing", "identified error", "standard deviation", "95 % interval"],
        [
            [
                name,
                f"{1e3 * result.nominal.vector()[k]:.4f} mm"
                if PARAMETER_UNITS[k] == "m"
                else "0 rad",
                _value(k, result.model.vector()[k] - result.nominal.vector()[k]),
                _value(k, result.std[k]).lstrip("+"),
                "± " + _value(k, CI_SIGMAS * result.std[k]).lstrip("+"),
            ]
            for k, name in enumerate(PARAMETER_NAMES)
        ],
    )
    if result.unidentifiable:
        held = "".join(
            "<li>" + escape(" ".join(f"{c:+.3g} {n}" for n, c in combo.items())) + "</li>"
            for combo in result.unidentifiable
        )
        held = (
            "<p>These combinations of the parameters could not be determined by the poses; "
            f"they are held at the drawing's values:</p><ul>{held}</ul>"
        )
    else:
        held = "<p>Every parameter is determined by the poses.</p>"
    sections = [
        ("Summary", summary),
        ("Residuals before and after, per axis", image(images, "residuals", "residuals")),
        ("Parameters", params + image(images, "parameters", "parameters") + held),
        ("Poses", image(images, "poses", "poses in the cube")),
        (
            "Model",
            '<p class="note">Each leg is a distance constraint between the tool point and '
            "a point of its carriage, ||P - a_i - q_i u_i|| = L_i: carriage points a_i, "
            "rail directions u_i (two tilt angles each) and leg lengths L_i, 18 parameters. "
            "Parallelogram defects that would turn the platform are outside the model. "
            f"Files next to this page: {YAML_NAME}, {CSV_NAME} (SI units).</p>",
        ),
    ]
    subtitle = (
        f"{len(data)} poses from {escape(Path(data.source).name)}; drawing: leg length "
        f"{1e3 * result.nominal.mean_length:.2f} mm"
    )
    return page("Orthoglide calibration", subtitle, sections)


def write_calibration_outputs(
    directory: str | os.PathLike[str],
    calibration: Calibration,
    result: Identification,
    data: Measurements,
    *,
    force: bool = False,
) -> Path:
    """Write the calibration directory atomically (see the module).

    Args:
        directory: The directory (refused when it holds files the package did
            not write, unless ``force``).
        calibration: The calibration to save.
        result: The identification it came from (residuals, outliers).
        data: The measurements.
        force: Write into a non-empty directory that the package did not write.

    Returns:
        The path of ``calibration.yaml``.
    """
    html = calibration_html(calibration, result, data)
    csv = residuals_csv(result, data)
    with atomic_directory(directory, force=force) as tmp:
        write_calibration(tmp / YAML_NAME, calibration)
        (tmp / HTML_NAME).write_text(html, encoding="utf-8")
        (tmp / CSV_NAME).write_text(csv, encoding="utf-8")
    return Path(directory) / YAML_NAME


def calibration_payload(calibration: Calibration) -> dict[str, Any]:
    """The ``--json`` object of ``orthoglide calibrate`` (strict JSON values)."""
    return {
        "rms_before": calibration.rms_before,
        "rms_after": calibration.rms_after,
        "noise_estimate": calibration.noise_estimate,
        "outliers": list(calibration.outliers),
        "unidentifiable": [dict(c) for c in calibration.unidentifiable],
        "parameters": calibration.parameters(),
        "poses": calibration.poses,
        "measurements_sha256": calibration.measurements_sha256,
        "design": calibration.design,
    }
