"""The limits' rows of a section, recomputed only where their inputs changed.

A window (:mod:`~orthoglide_pin.planning.windows`) is planned several times:
the motor-torque bounds are taken again around each pass's plan, and a plan
whose verification exceeds a limit is planned again with that limit tightened
around the overshoot (:mod:`~orthoglide_pin.planning.tighten`). Between two
such plans the inputs of a point's rows (its squared-speed bound and previous
squared speed, its tightening factors) change only on a small part of the
window: the re-plan moves the speeds only near the tightened points. The rows
of a point depend on that point's inputs alone
(:func:`~orthoglide_pin.planning.limits.rows`), so :class:`RowCache` keeps the
last rows and computes again only the points whose inputs differ: the same
numbers as computing them all. With numba, TOPP-RA's passes are kept likewise
(:class:`~orthoglide_pin.planning.reach_compiled.ReachAgain`), and so are the
friction and available torque at the samples of each point's ``[0, X]``
(:func:`~orthoglide_pin.planning.rows_compiled.sample_values`), which depend
on its bound ``X`` alone: the passes of a plan and its re-plans keep the bound
on most points, and only the probes around the previous speeds are evaluated
again there.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.path_forms import PathForms
from orthoglide_pin.planning import limits as limits_module
from orthoglide_pin.planning.limits import PlanLimits, Scales, motors, rows, samples
from orthoglide_pin.planning.reach_compiled import AVAILABLE, ReachAgain
from orthoglide_pin.planning.rows_compiled import sample_values

FloatArray = NDArray[np.float64]
Rows = tuple[FloatArray, FloatArray, FloatArray]

#: The factors that the rows read (the others act on the speed bound only).
FACTORS = ("slider_acceleration", "motor_torque")
_FORMS = ("q", "dq", "ddq", "a", "b", "c")


class RowCache:
    """:func:`~orthoglide_pin.planning.limits.rows` of one section, kept between its plans.

    Args:
        limits: The limits.
        forms: The path forms at the section's ``n`` planning-grid points.
    """

    def __init__(self, limits: PlanLimits, forms: PathForms) -> None:
        self.limits, self.forms = limits, forms
        self._inputs: FloatArray | None = None
        self._rows: Rows | None = None
        self.computed = 0  # points whose rows were computed, over all calls
        self._values: tuple[FloatArray, FloatArray] | None = None
        self._values_at: FloatArray | None = None  # the bounds X of the values
        #: The passes kept likewise (with numba): only the stages whose rows changed.
        self.passes = ReachAgain() if AVAILABLE else None

    def _key(self, x_high: FloatArray, x0: FloatArray, scales: Scales) -> FloatArray:
        n = x_high.size
        cols = [x_high, x0]
        cols += [np.broadcast_to(np.asarray(scales.get(k), dtype=float), (n,)) for k in FACTORS]
        return np.stack(cols, axis=1)

    def rows(self, x_high: FloatArray, x0: FloatArray, scales: Scales) -> Rows:
        """``rows(limits, forms, x_high, x0, scales)``, computed only where the inputs changed."""
        key = self._key(x_high, x0, scales)
        n = key.shape[0]
        values = self._sample_values(x_high)
        idx = None if self._inputs is None else np.flatnonzero((key != self._inputs).any(axis=1))
        if idx is None or self._rows is None or idx.size == n:  # every point: no copy, no splice
            out = rows(self.limits, self.forms, x_high, x0, scales, values=values)
            self.computed += n
        else:
            self.computed += idx.size
            out = (self._rows[0].copy(), self._rows[1].copy(), self._rows[2].copy())
            if idx.size:
                forms = PathForms(*(getattr(self.forms, name)[idx] for name in _FORMS))
                sub = Scales(
                    {
                        name: f if isinstance(f, float) else np.asarray(f)[idx]
                        for name, f in scales.factors.items()
                    }
                )
                ends = (idx == 0) | (idx == n - 1)
                some = None if values is None else (values[0][idx], values[1][idx])
                part = rows(self.limits, forms, x_high[idx], x0[idx], sub, ends, some)
                for whole, piece in zip(out, part, strict=True):
                    whole[idx] = piece
        self._inputs, self._rows = key, out
        return out

    def _sample_values(self, x_high: FloatArray) -> tuple[FloatArray, FloatArray] | None:
        """The compiled rows' values at the samples of ``[0, X]``, kept where ``X`` is."""
        if not (limits_module.COMPILED and self.limits.limits_torque):
            return None
        dq = self.forms.dq
        if self._values is None or self._values_at is None:
            self._values = sample_values(motors(self.limits), dq, samples(x_high))
        else:
            idx = np.flatnonzero(self._values_at != x_high)
            if idx.size:
                h, av = sample_values(motors(self.limits), dq[idx], samples(x_high[idx]))
                self._values[0][idx], self._values[1][idx] = h, av
        self._values_at = x_high.copy()
        return self._values
