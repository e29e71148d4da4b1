"""The plan sampled for the cut: where the tool is, where it feeds, and whether it cuts.

:func:`cut_samples` evaluates a plan every ``dt`` seconds (and at its end) from
each section's exact time law, as ``trajectory.csv`` does
(:mod:`~orthoglide_pin.planning.sampling`), without the dynamics: the tool
point, the path's unit tangent, the planned path speed and the program line.
A sample **cuts** when it lies on a feed move (``G1``, ``G2``, ``G3`` and the
blends between them; never a rapid ``G0`` nor a dwell), on a line that an
engagement of the cut covers
(:meth:`~orthoglide_pin.machining.cutting.CutConditions.engagement_at`),
and when the path runs in the feed plane rather than along the tool's axis:
the tangent's share in the plane normal to the tool axis is at least
:data:`MIN_PLANE_SHARE`. A plunge along the tool's axis is drilling, not
milling: it carries no milling force in this model. Lines above the part are
told apart by the engagement's line ranges (the model does not know the
part's stock).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import instance_of, number_in, size_within, text
from orthoglide_pin.exceptions import CutConditionsError
from orthoglide_pin.machining._checks import RPM_PER_RAD_S, number
from orthoglide_pin.machining.cutting import CutConditions
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.program.words import read_line

FloatArray = NDArray[np.float64]

#: Smallest share of the path's tangent in the feed plane for a sample to mill [-].
MIN_PLANE_SHARE: Final[float] = 0.2
#: Most samples of one call [-].
MAX_SAMPLES: Final[int] = 1_000_000
#: Range of the sampling step [s].
MIN_DT: Final[float] = 1e-4
MAX_DT: Final[float] = 1.0


@dataclass(frozen=True)
class CutSamples:
    """A plan sampled in time, with what the cut needs.

    Attributes:
        t: Times [s], (n,).
        points: Tool points [m], (n, 3), world frame.
        tangent: Unit tangent of the path [-], (n, 3), world frame (zero at rest
            outside a section).
        speed: Planned path speed [m/s], (n,).
        line: Program line of the block the tool is on, (n,) (0 at rest outside a block).
        cutting: Whether the sample mills (see the module), (n,).
        tool_axis: The tool's axis, the program's +Z in the world frame, (3,).
    """

    t: FloatArray
    points: FloatArray
    tangent: FloatArray
    speed: FloatArray
    line: NDArray[np.intp]
    cutting: NDArray[np.bool_]
    tool_axis: FloatArray

    @property
    def plane_tangent(self) -> FloatArray:
        """The tangent's part in the feed plane [-], (n, 3)."""
        z = self.tool_axis
        return np.asarray(self.tangent - np.outer(self.tangent @ z, z), dtype=np.float64)


def sample_times(plan: Plan, dt: float) -> FloatArray:
    """Every ``dt`` over the plan, and its end [s].

    Raises:
        InvalidParameterError: A ``dt`` outside ``[MIN_DT, MAX_DT]``, or more
            than :data:`MAX_SAMPLES` samples (counted before any is made).
    """
    dt = number_in("dt", dt, MIN_DT, MAX_DT, "[s]")
    count = np.floor(plan.cycle_time / dt) + 1.0
    size_within("dt", dt, count + 1.0, MAX_SAMPLES, f"samples over {plan.cycle_time:.6g} s")
    t = np.arange(int(count), dtype=np.float64) * dt
    if t[-1] < plan.cycle_time:
        t = np.append(t, plan.cycle_time)
    return t


def cut_samples(plan: Plan, cut: CutConditions, dt: float) -> CutSamples:
    """The plan every ``dt`` [s], with the cutting flag (see the module).

    Raises:
        InvalidParameterError: A bad plan, cut or ``dt``.
    """
    plan = instance_of("plan", plan, Plan, "a Plan (plan_program)")
    cut = instance_of("cut", cut, CutConditions, "CutConditions (read_cut_file)")
    t = sample_times(plan, dt)
    n = t.size
    blocks = plan.path.program.blocks
    p = np.broadcast_to(plan.path.program.start, (n, 3)).copy()
    tangent, speed = np.zeros((n, 3)), np.zeros(n)
    line = np.zeros(n, dtype=np.intp)
    feeding = np.zeros(n, dtype=bool)
    for r in plan.sections:
        end = r.start + r.duration
        if r.plan is None:  # a lone dwell: the tool rests where it is
            continue
        sec = r.section
        mask = (t >= r.start) & (t <= end)
        later = t > end
        last = sec.pieces[-1]
        p[later] = last.evaluate(np.array([last.length]))[0][0]
        if not mask.any():
            continue
        s, v, _ = r.plan.at_times(t[mask] - r.start)
        j_of = np.clip(np.searchsorted(sec.offsets, s, side="right") - 1, 0, len(sec.pieces) - 1)
        pp, d1 = np.zeros((s.size, 3)), np.zeros((s.size, 3))
        ln, fd = np.zeros(s.size, dtype=np.intp), np.zeros(s.size, dtype=bool)
        for j in np.unique(j_of):
            sel = j_of == j
            piece = sec.pieces[j]
            pp[sel], d1[sel], _ = piece.evaluate(s[sel] - sec.offsets[j])
            ln[sel] = blocks[piece.block].line
            fd[sel] = piece.feed is not None
        p[mask], tangent[mask], speed[mask], line[mask], feeding[mask] = pp, d1, v, ln, fd
        tangent[later], speed[later], line[later], feeding[later] = 0.0, 0.0, 0, False
    axis = np.asarray(plan.path.program.axes.matrix[:, 2], dtype=np.float64)
    engaged = np.zeros(n, dtype=bool)
    for ln_value in np.unique(line[feeding]):
        engaged[line == ln_value] = cut.engagement_at(int(ln_value)) is not None
    plane = np.linalg.norm(tangent - np.outer(tangent @ axis, axis), axis=1)
    cutting = feeding & engaged & (plane >= MIN_PLANE_SHARE)
    return CutSamples(t, p, tangent, speed, line, cutting, axis)


def program_spindle_speed(program_text: str) -> float | None:
    """The spindle speed of a program's ``S`` words [rad/s], or ``None`` when it has none.

    Every ``S`` word of the program must give the same speed (in rpm, as
    written); comments and block-deleted lines are read as the program
    reader reads them.

    Raises:
        CutConditionsError: Two ``S`` words that differ (naming their lines),
            or a speed outside the plausible range.
    """
    found: tuple[int, float] | None = None
    for number_, raw in enumerate(text("program_text", program_text).splitlines(), start=1):
        for word in read_line(raw, number_).words:
            if word.letter != "S":
                continue
            if found is not None and word.value != found[1]:
                raise CutConditionsError(
                    "S", word.value, f"one spindle speed per program (line {found[0]} says "
                    f"S{found[1]:g}, line {number_} S{word.value:g}): give it in the cut file"
                )  # fmt: skip
            found = (number_, word.value)
    if found is None:
        return None
    return number("spindle_speed", found[1]) / RPM_PER_RAD_S
