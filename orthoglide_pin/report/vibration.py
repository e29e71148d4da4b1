"""The report's vibration section: the machine's lowest natural frequency over the cube.

:func:`vibration_section` evaluates the platform model of
:mod:`orthoglide_pin.elasticity.modes` (vectorised over points) on the report's
cube grid, at most :data:`MAX_CUBE_RESOLUTION` points per edge and an odd
number of them, so that the grid's middle layer is the cube's centre plane:

* the lowest natural frequency over the cube [Hz] and where it occurs;
* its map on the slices ``z`` = lower face, centre and upper face (layers of
  the grid), drawn by :func:`vibration_figure`;
* the modes at that worst point: frequencies, the tool's direction, the
  platform's rotation per metre of tool motion and the kinetic-energy shares;
* the full model (members with their beam masses) at the worst point, its
  :data:`CHECK_MODES` lowest frequencies, as a cross-check of the platform
  model, with their relative difference;
* with a minimum frequency, a verdict row (:func:`vibration_rows`): required
  the minimum, available the lower of the platform model's lowest frequency
  over the cube and the full model's at that point, margin
  ``1 - required / available``.

The drives: with the report's drive, its rotary inertia is reflected onto each
carriage (:func:`~orthoglide_pin.elasticity.mass.reflected_mass`); without one
the carriages move alone, and every output says so.
"""

from __future__ import annotations

import html
import io
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import integer, positive_number
from orthoglide_pin.drives.motor import Drive
from orthoglide_pin.elasticity.modes import NaturalModes, natural_frequencies
from orthoglide_pin.kinetostatics.workspace import Grid, cube_grid
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.report.verdict import margin_value

FloatArray = NDArray[np.float64]

__all__ = [
    "CHECK_MODES",
    "VibrationSection",
    "vibration_csv",
    "vibration_dict",
    "vibration_figure",
    "vibration_html",
    "vibration_rows",
    "vibration_section",
]

#: Largest cube resolution of the section: the platform model costs about twice
#: the stiffness section's time per point, so that 15^3 points and the full
#: model at one point take about the stiffness section's time. Finer report
#: grids are coarsened to it (the least frequency is at a corner, which every
#: grid has).
MAX_CUBE_RESOLUTION: Final[int] = 15
#: Modes of the full model computed at the worst point (the cross-check).
CHECK_MODES: Final[int] = 3
#: Criterion of the verdict row.
CRITERION: Final = "vibration: lowest natural frequency vs minimum"
#: The slices: label and the layer's place in the grid (0: lower face, 1: upper face).
SLICES: Final = (("lower face", 0.0), ("centre", 0.5), ("upper face", 1.0))
#: Energy parts of a mode, in the order of :attr:`NaturalModes.energy`.
PARTS: Final = ("platform", "carriages", "members")
_MM: Final = 1e3
NO_DRIVE: Final = "carriages alone, no drive inertia"


@dataclass(frozen=True)
class VibrationSection:
    """The lowest natural frequency over the cube, the worst point's modes, the check.

    Attributes:
        grid: The cube grid (odd points per edge).
        lowest: The lowest natural frequency at each grid point [Hz], shape (n, n, n).
        direction: The tool's direction in that mode (unit), shape (n, n, n, 3).
        worst: The platform model's modes at the worst point (six).
        check: The full model's :data:`CHECK_MODES` lowest modes at that point.
        min_frequency: The minimum frequency asked [Hz], or ``None`` (no verdict).
    """

    grid: Grid
    lowest: FloatArray
    direction: FloatArray
    worst: NaturalModes
    check: NaturalModes
    min_frequency: float | None = None

    @property
    def worst_point(self) -> FloatArray:
        """Where the lowest frequency is least [m], shape (3,)."""
        return np.asarray(self.worst.points, dtype=float).reshape(3)

    @property
    def lowest_frequency(self) -> float:
        """The least lowest frequency over the cube, platform model [Hz]."""
        return float(self.lowest.min())

    @property
    def difference(self) -> FloatArray:
        """``platform / full - 1`` of the checked modes at the worst point [-], (CHECK_MODES,)."""
        full = self.check.frequencies.reshape(-1)
        return np.asarray(self.worst.frequencies.reshape(-1)[: full.size] / full - 1.0)

    @property
    def available(self) -> float:
        """The frequency the verdict judges [Hz]: the lower of the two models' there."""
        return min(self.lowest_frequency, float(self.check.frequencies.reshape(-1)[0]))

    @property
    def margin(self) -> float | None:
        """``1 - min_frequency / available``, or ``None`` without a minimum."""
        if self.min_frequency is None:
            return None
        return margin_value(self.min_frequency, self.available)

    @property
    def drive(self) -> str:
        """The drives' part in the modes, in words."""
        mass = self.worst.drive_mass
        if mass <= 0.0:
            return NO_DRIVE
        return f"drive inertia {mass:.4g} kg reflected onto each carriage (the report's drive)"

    def slices(self) -> list[tuple[str, float, FloatArray]]:
        """``(label, z [m], lowest frequency [Hz] of shape (n, n))`` per slice."""
        n = self.grid.z.size
        out = []
        for label, where in SLICES:
            k = round(where * (n - 1))
            out.append((f"z = {label}", float(self.grid.z[k]), self.lowest[:, :, k]))
        return out


def _worst_modes(modes: NaturalModes, index: int) -> NaturalModes:
    """The modes of one point (flat ``index``) of a batch."""
    count = modes.frequencies.shape[-1]
    return NaturalModes(
        points=modes.points.reshape(-1, 3)[index],
        frequencies=modes.frequencies.reshape(-1, count)[index],
        direction=modes.direction.reshape(-1, count, 3)[index],
        rotation=modes.rotation.reshape(-1, count, 3)[index],
        energy=modes.energy.reshape(-1, count, 3)[index],
        model=modes.model,
        drive_mass=modes.drive_mass,
        segments=None,
    )


def vibration_section(
    params: OrthoglideParams,
    corner: FloatArray,
    side: float,
    drive: Drive | None = None,
    cube_resolution: int = MAX_CUBE_RESOLUTION,
    min_frequency: float | None = None,
) -> VibrationSection:
    """Evaluate the natural frequencies over the cube ``[corner, corner + side]`` (see the module).

    Args:
        params: The machine.
        corner: Lowest corner of the cube [m], shape (3,).
        side: Side of the cube [m].
        drive: The drive whose rotary inertia is reflected onto each carriage,
            or ``None`` (the carriages alone).
        cube_resolution: Points per edge of the cube grid (at most
            :data:`MAX_CUBE_RESOLUTION`; an even number is raised by one).
        min_frequency: The lowest natural frequency the machine must have [Hz],
            or ``None`` for no verdict.

    Raises:
        InvalidParameterError: A bad minimum frequency, drive or grid.
        UnreachablePointError, SingularConfigurationError: The cube leaves the
            slider limits or meets a singularity.
    """
    if min_frequency is not None:
        min_frequency = positive_number(
            "min_frequency", min_frequency, "a positive frequency [Hz]"
        )
    n = min(integer("cube_resolution", cube_resolution, 2), MAX_CUBE_RESOLUTION)
    grid = cube_grid(corner, side, n + 1 - n % 2)
    modes = natural_frequencies(params, grid.points(), drive, count=6, model="platform")
    lowest = np.asarray(modes.lowest, dtype=float)
    index = int(np.argmin(lowest))
    worst = _worst_modes(modes, index)
    check = natural_frequencies(params, worst.points, drive, count=CHECK_MODES, model="full")
    return VibrationSection(
        grid, lowest, np.asarray(modes.direction[..., 0, :]), worst, check, min_frequency
    )


def vibration_rows(section: VibrationSection) -> tuple[tuple[Any, ...], ...]:
    """The verdict row ``(None, criterion, required, available, "Hz", margin)``.

    None without a minimum frequency.
    """
    if section.min_frequency is None:
        return ()
    return ((None, CRITERION, section.min_frequency, section.available, "Hz", section.margin),)


def vibration_dict(section: VibrationSection) -> dict[str, Any]:
    """The section's figures, SI units, JSON-ready (assumptions included)."""
    margin = section.margin
    return {
        "model": "platform",
        "drive": section.drive,
        "drive_mass": section.worst.drive_mass,
        "grid_points": int(section.grid.x.size),
        "lowest_frequency": section.lowest_frequency,
        "worst_point": section.worst_point.tolist(),
        "median_lowest_frequency": float(np.median(section.lowest)),
        "highest_lowest_frequency": float(section.lowest.max()),
        "slices": [
            {"label": label, "z": z, "lowest_frequency": float(values.min())}
            for label, z, values in section.slices()
        ],
        "worst_modes": {
            k: v
            for k, v in section.worst.to_dict().items()
            if k not in ("segments", "assumptions")
        },
        "check": {
            "model": "full",
            "frequencies": section.check.frequencies.reshape(-1).tolist(),
            "segments": None
            if section.check.segments is None
            else int(section.check.segments.reshape(-1)[0]),
            "difference": section.difference.tolist(),
        },
        "min_frequency": section.min_frequency,
        "available": section.available,
        "margin": margin,
        "passed": None if margin is None else margin >= 0.0,
        "assumptions": [
            *section.worst.assumptions(),
            "The full model checks the worst point; the verdict takes the lower of the two.",
        ],
    }


def vibration_csv(section: VibrationSection) -> str:
    """``vibration.csv``: every grid point, its lowest frequency [Hz] and that mode's direction."""
    pts = section.grid.points().reshape(-1, 3)
    table = np.column_stack([pts, section.lowest.reshape(-1), section.direction.reshape(-1, 3)])
    buf = io.StringIO()
    np.savetxt(buf, table, delimiter=",", fmt="%.12g")
    header = "x,y,z,lowest_frequency,direction_x,direction_y,direction_z\n"
    return header + buf.getvalue()


def vibration_figure(section: VibrationSection, dpi: int = 90) -> bytes:
    """Maps of the lowest natural frequency [Hz] on the slices, as PNG bytes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    slices = section.slices()
    fig = Figure(figsize=(4.0 * len(slices) + 1.2, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, len(slices), squeeze=False, sharex=True, sharey=True)[0]
    lo, hi = float(section.lowest.min()), float(section.lowest.max())
    x, y = section.grid.x * _MM, section.grid.y * _MM
    mesh = None
    for ax, (label, z, values) in zip(axes, slices, strict=True):
        mesh = ax.pcolormesh(x, y, values.T, shading="gouraud", vmin=lo, vmax=hi)
        i, j = np.unravel_index(np.argmin(values), values.shape)
        ax.plot(x[i], y[j], "o", ms=9, mfc="none", mec="red", mew=2, clip_on=False)
        ax.set_title(f"{label}, z = {z * _MM:.1f} mm", fontsize=9)
        ax.set_aspect("equal")
    assert mesh is not None
    fig.colorbar(mesh, ax=list(axes), label="lowest natural frequency [Hz]", shrink=0.8)
    fig.supxlabel("tool position x [mm]")
    fig.supylabel("tool position y [mm]")
    fig.suptitle(
        f"Lowest natural frequency, platform model, {section.drive} "
        "(circle: the least of each slice)",
        fontsize=10,
    )
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return buf.getvalue()


def _vec(values: Any, spec: str) -> str:
    return "(" + ", ".join(format(float(v), spec) for v in values) + ")"


def vibration_html(section: VibrationSection, image: str) -> str:
    """The page's section: the figures, the maps (an ``<img>`` tag), the modes, the assumptions."""
    s = vibration_dict(section)
    where = _vec(_MM * section.worst_point, ".1f")
    check = ", ".join(
        f"{f:.4g} Hz ({100 * d:+.1f} %)"
        for f, d in zip(s["check"]["frequencies"], s["check"]["difference"], strict=True)
    )
    rows = [
        ("lowest natural frequency over the cube", f"{s['lowest_frequency']:.4g} Hz"),
        ("where", f"{where} mm"),
        ("median over the cube", f"{s['median_lowest_frequency']:.4g} Hz"),
        ("full model at that point (platform model's difference)", check),
        ("drives", section.drive),
    ]
    classes = [""] * len(rows)
    if section.min_frequency is not None:
        passed = s["passed"]
        rows.append(
            (
                f"minimum frequency {section.min_frequency:g} Hz",
                f"{'PASS' if passed else 'FAIL'}, margin {100 * s['margin']:+.1f} %",
            )
        )
        classes.append("pass" if passed else "fail")
    table = "".join(
        f'<tr class="{c}"><td class="text">{html.escape(a)}</td><td>{html.escape(b)}</td></tr>'
        for (a, b), c in zip(rows, classes, strict=True)
    )
    head = "".join(
        f"<th>{html.escape(h)}</th>"
        for h in (
            "mode",
            "frequency [Hz]",
            "tool direction",
            "platform rotation [rad/m]",
            "energy: platform, carriages, members",
        )
    )
    modes = "".join(
        f"<tr><td>{k}</td><td>{m['frequency']:.4g}</td>"
        f"<td>{html.escape(_vec(m['tool_direction'], '+.3f'))}</td>"
        f"<td>{html.escape(_vec(m['platform_rotation'], '+.3g'))}</td>"
        f"<td>{html.escape(_vec([m['energy'][p] for p in PARTS], '.2f'))}</td></tr>"
        for k, m in enumerate(s["worst_modes"]["shapes"], start=1)
    )
    notes = "".join(f'<p class="note">{html.escape(a)}</p>' for a in s["assumptions"])
    return (
        f"<table>{table}</table>{image}"
        f"<h3>Modes at the worst point {html.escape(where)} mm (platform model)</h3>"
        f"<table><tr>{head}</tr>{modes}</table>{notes}"
    )
