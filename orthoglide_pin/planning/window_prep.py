"""A window of a long section made ready to plan: sampled, checked, its path forms.

:mod:`~orthoglide_pin.planning.windows` plans a long section window after
window; each window's pieces are first sampled on the fine (verification)
grid, checked inside the workspace and the slider limits, given their path
forms (:func:`~orthoglide_pin.dynamics.path_forms.path_forms`) and their
speed caps: :func:`prepare`, run on a second thread for the next window while
one is planned.

A window reaches past the pieces it keeps by a look-ahead, and the next
window starts where that look-ahead starts: the two overlap. A sample's
position, tangent, curvature and path forms depend only on its piece and its
arc length along the piece, so :func:`prepare` takes those of the overlap from
the window before (``before``) and evaluates only the pieces past it. Only
the last sample of the window before is evaluated again: there it ended its
last piece, here that point is the first of the next piece (a point at the
junction of two pieces is evaluated on the later one). The samples are the
same numbers as those of a window prepared alone
(``tests/planning/test_window_prep.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.batch import coarse_forms, coarse_samples, section_forms
from orthoglide_pin.planning.calibrated import CalibratedKinematics, calibrated_forms
from orthoglide_pin.planning.controller import rapid_caps
from orthoglide_pin.planning.limits import PlanLimits, Scales
from orthoglide_pin.planning.parametrize import SectionInput
from orthoglide_pin.planning.path import Samples, Section
from orthoglide_pin.planning.run_batch import check_run, run_feeds
from orthoglide_pin.planning.sample_batch import sample_batch
from orthoglide_pin.planning.verify import REFINE

FloatArray = NDArray[np.float64]

_FORMS = ("q", "dq", "ddq", "a", "b", "c")
_SAMPLES = ("s", "p", "dp", "ddp", "piece")


@dataclass(frozen=True)
class WindowSetting:
    """What every window of a section is planned with.

    Attributes:
        section: The section.
        lines: The program line of each of its pieces, (k,).
        dyn: The inverse dynamics.
        limits: The limits.
        g: Gravity [m/s^2], (3,).
        w: The tool wrench (6,), or ``None``.
        step: Largest spacing of the planning grid [m].
        calibration: A calibration, or ``None``.
        max_rounds: Plans of a window at most.
        rapid_override: The rapid override, in (0, 1].
    """

    section: Section
    lines: NDArray[np.intp]
    dyn: ClosedLoopDynamics
    limits: PlanLimits
    g: FloatArray
    w: FloatArray | None
    step: float
    calibration: CalibratedKinematics | None
    max_rounds: int
    rapid_override: float = 1.0


@dataclass(frozen=True)
class Prepared:
    """A window's pieces ``lo:hi`` sampled, checked, their path forms: all but its start speed.

    Attributes:
        lo: Its first piece in the section.
        hi: The piece after its last.
        sub: Its pieces as a section of their own (arc lengths from ``lo``'s start).
        fine: Its samples on the fine grid.
        grid: Its samples on the planning grid (every ``REFINE``-th fine one).
        fine_lines: The program line of each fine sample.
        fine_forms: The path forms at the fine samples.
        fine_feed: The path-speed cap at each fine sample [m/s].
        inp: The planner's input on the planning grid.
    """

    lo: int
    hi: int
    sub: Section
    fine: Samples
    grid: Samples
    fine_lines: NDArray[np.intp]
    fine_forms: PathForms
    fine_feed: FloatArray
    inp: SectionInput


def sub_section(section: Section, lo: int, hi: int) -> Section:
    """Pieces ``lo:hi`` of a section, their arc lengths from piece ``lo``'s start."""
    return Section(section.pieces[lo:hi], section.offsets[lo : hi + 1] - section.offsets[lo])


def _overlap(before: Prepared | None, lo: int, hi: int) -> slice | None:
    """The samples of ``before`` that are pieces ``lo:hi``'s first ones, or ``None``."""
    if before is None or not before.lo <= lo < before.hi < hi:
        return None
    first = int(np.searchsorted(before.fine.piece, lo - before.lo, side="left"))
    return slice(first, before.fine.s.size - 1)  # its last sample ended its last piece


def prepare(st: WindowSetting, lo: int, hi: int, before: Prepared | None = None) -> Prepared:
    """Pieces ``lo:hi`` sampled, checked inside the workspace, their path forms and caps.

    Args:
        st: The section's setting.
        lo: The window's first piece.
        hi: The piece after its last.
        before: The window prepared before it, whose samples and path forms of
            the pieces the two share are taken (see the module), or ``None``.

    Raises:
        ProgramError: A sample outside the cube or the slider limits, naming its line.
    """
    section, lines, limits, calibration = st.section, st.lines, st.limits, st.calibration
    params: OrthoglideParams = st.dyn.closed_loop.params
    sub = sub_section(section, lo, hi)
    shared = _overlap(before, lo, hi)
    known = None
    if shared is not None:
        assert before is not None
        known = (before.fine.p[shared], before.fine.dp[shared], before.fine.ddp[shared])
    fine = sample_batch(sub, st.step, refine=REFINE, known=known)
    m = 0 if known is None else known[0].shape[0]
    if m and int(np.searchsorted(fine.piece, before.hi - lo)) != m:  # type: ignore[union-attr]
        raise AssertionError("the windows' samples do not line up")  # pragma: no cover
    fine_lines = lines[lo:hi][fine.piece]
    new = Samples(*(getattr(fine, n)[m:] for n in _SAMPLES))
    check_run(params, calibration, [new], fine_lines[m:])
    fine_forms = section_forms(st.dyn, [new], st.g, st.w)[0]
    if m:
        assert before is not None and shared is not None
        fine_forms = PathForms(
            *(np.concatenate([getattr(before.fine_forms, n)[shared], getattr(fine_forms, n)])
              for n in _FORMS)
        )  # fmt: skip
    grid = coarse_samples(fine)
    forms = coarse_forms(fine_forms)
    if calibration is not None:
        forms = calibrated_forms(calibration, forms, grid.p, grid.dp, grid.ddp)
    caps = rapid_caps(run_feeds([sub], [grid])[0], forms, limits, st.rapid_override)
    inp = SectionInput(grid.s, forms, caps, Scales())
    feed = run_feeds([sub], [fine])[0]
    return Prepared(lo, hi, sub, fine, grid, fine_lines, fine_forms, feed, inp)
