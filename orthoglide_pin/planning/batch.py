"""A plan's sections evaluated in one batch: path forms, planning grids, verification.

A program's sections are sampled once on the fine (verification) grid; the
planning grid is every ``REFINE``-th sample of it (:func:`coarse_samples`,
:func:`coarse_forms`). The path forms of the closed-loop dynamics
(:func:`~orthoglide_pin.dynamics.path_forms.path_forms`) of all sections are
computed in one batch (:func:`section_forms`), and so is the verification of
their time laws on the fine grid (:func:`check_sections`, through
:func:`~orthoglide_pin.planning.verify.evaluate_forms`), kept joined
(:class:`RunMotions`: a section's motion is cut from it when asked for, the
worst use and binding time of every section taken on it, :class:`RunSummary`
keeping each section's last ones). :func:`~orthoglide_pin.planning.plan.plan_program` drives
them.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import overload

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.path_forms import PathForms, path_forms
from orthoglide_pin.planning.calibrated import CalibratedKinematics
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import SectionPlan, laws_at
from orthoglide_pin.planning.path import Samples
from orthoglide_pin.planning.run_batch import cut
from orthoglide_pin.planning.verify import BINDING, REFINE, Motion, evaluate_forms

FloatArray = NDArray[np.float64]


def section_forms(
    dyn: ClosedLoopDynamics, grids: list[Samples], g: FloatArray, w: FloatArray | None
) -> list[PathForms]:
    """The path forms of every section, from one batch."""
    if not grids:
        return []
    cat = [np.concatenate([getattr(x, name) for x in grids]) for name in ("p", "dp", "ddp")]
    forms = path_forms(dyn, *cat, gravity=g, wrench=w)
    sizes = [x.s.size for x in grids]
    fields = ("q", "dq", "ddq", "a", "b", "c")
    split = {name: cut(getattr(forms, name), sizes) for name in fields}
    return [PathForms(**{name: split[name][k] for name in fields}) for k in range(len(grids))]


def coarse_samples(fine: Samples) -> Samples:
    """The planning grid of a section from its fine grid (every ``REFINE``-th sample)."""
    return Samples(*(getattr(fine, n)[::REFINE] for n in ("s", "p", "dp", "ddp", "piece")))


def coarse_forms(forms: PathForms) -> PathForms:
    """The path forms at the planning grid from those at the fine grid."""
    return PathForms(*(getattr(forms, n)[::REFINE] for n in ("q", "dq", "ddq", "a", "b", "c")))


class RunMotions(Sequence[Motion]):
    """The motions of sections verified together: one per section, cut on demand.

    Their worst uses and binding times are taken on the joined motion, per
    section, without cutting it (a run of thousands of sections).

    Attributes:
        joined: The sections' motions laid end to end.
        starts: The first sample of each section, and the end, (k + 1,).
    """

    def __init__(self, joined: Motion, sizes: list[int]) -> None:
        self.joined = joined
        self.starts = np.concatenate([[0], np.cumsum(sizes)]).astype(np.intp)

    def __len__(self) -> int:
        return int(self.starts.size - 1)

    @overload
    def __getitem__(self, k: int) -> Motion: ...
    @overload
    def __getitem__(self, k: slice) -> Sequence[Motion]: ...
    def __getitem__(self, k: int | slice) -> Motion | Sequence[Motion]:
        if isinstance(k, slice):
            return [self[j] for j in range(len(self))[k]]
        k = range(len(self))[k]  # IndexError out of range, as a list
        if len(self) == 1:
            return self.joined
        return _cut(self.joined, slice(int(self.starts[k]), int(self.starts[k + 1])))

    def __iter__(self) -> Iterator[Motion]:
        return (self[k] for k in range(len(self)))

    def worst(self) -> dict[str, FloatArray]:
        """Each limit's largest use on each section [-], (k,) each."""
        firsts = self.starts[:-1]
        return {n: np.maximum.reduceat(u, firsts) for n, u in self.joined.uses.items()}

    def over(self, most: float) -> list[int]:
        """The sections where some limit's use exceeds ``most``, in order."""
        out = np.zeros(len(self), dtype=bool)
        for peak in self.worst().values():
            out |= ~(peak <= most)
        over: list[int] = np.flatnonzero(out).tolist()
        return over

    def binding(self) -> dict[str, FloatArray]:
        """The time each limit binds on each section [s], (k,) each (see :func:`binding_time`)."""
        t = self.joined.t
        dt = np.diff(t)
        dt[self.starts[1:-1] - 1] = 0.0  # no time from a section's end to the next one's start
        w = np.zeros_like(t)
        w[:-1] += 0.5 * dt
        w[1:] += 0.5 * dt
        firsts = self.starts[:-1]
        return {
            n: np.add.reduceat(np.where(u >= BINDING, w, 0.0), firsts)
            for n, u in self.joined.uses.items()
        }


class RunSummary:
    """The worst uses and binding times of a run's sections, each from its last verification."""

    def __init__(self, count: int) -> None:
        self.count = count
        self.peaks: dict[str, FloatArray] = {}
        self.binds: dict[str, FloatArray] = {}

    def add(self, sections: list[int], motions: RunMotions) -> None:
        """Keep the verification of ``sections`` (indices in the run), replacing any earlier."""
        for store, got in ((self.peaks, motions.worst()), (self.binds, motions.binding())):
            for name, values in got.items():
                store.setdefault(name, np.zeros(self.count))[sections] = values

    def totals(self) -> tuple[dict[str, float], dict[str, float]]:
        """The largest use of each limit, and the time each binds, summed in order."""
        binding = {}
        for name, values in self.binds.items():
            total = 0.0
            for v in values.tolist():
                total += v
            binding[name] = total
        return {n: max(0.0, float(p.max())) for n, p in self.peaks.items()}, binding


def check_sections(
    forms: list[PathForms],
    fines: list[Samples],
    laws: list[SectionPlan | None],
    feeds: list[FloatArray],
    limits: PlanLimits,
    calibration: CalibratedKinematics | None = None,
) -> RunMotions:
    """Each section verified on its fine grid, from the path forms there, in one batch."""
    assert all(law is not None for law in laws)
    t, sd, sdd = laws_at(laws, [fine.s for fine in fines])  # type: ignore[arg-type]

    def joined(parts: list[FloatArray]) -> FloatArray:
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    s, p, dp, ddp = (joined([getattr(f, n) for f in fines]) for n in ("s", "p", "dp", "ddp"))
    samples = Samples(s, p, dp, ddp, np.concatenate([f.piece for f in fines]))
    cat = PathForms(
        *(joined([getattr(f, n) for f in forms]) for n in ("q", "dq", "ddq", "a", "b", "c"))
    )
    motion = evaluate_forms(
        cat, samples, t, sd, sdd, joined(feeds), limits, calibration=calibration
    )
    return RunMotions(motion, [f.s.size for f in fines])


def changed_samples(x_old: FloatArray, x_new: FloatArray, fine_size: int) -> NDArray[np.bool_]:
    """The fine samples whose verification a new plan on the same grid may change, (m,).

    A fine sample's speed and acceleration come from the squared speeds at the
    two ends of its planning-grid interval (:meth:`SectionPlan.at_lengths`), so
    only the samples of intervals next to a point whose squared speed changed
    (one interval more on either side: a sample on a grid point may belong to
    either) can change. The planning grid is every ``REFINE``-th fine sample.
    """
    n = x_old.size
    assert fine_size == (n - 1) * REFINE + 1
    moved = x_old != x_new
    hit = moved[:-1] | moved[1:]  # intervals with a changed end
    hit[1:] |= hit[:-1].copy()
    hit[:-1] |= hit[1:].copy()
    k = np.minimum(np.arange(fine_size) // REFINE, n - 2)
    return np.asarray(hit[k])


def check_again(
    forms: PathForms,
    fine: Samples,
    law: SectionPlan,
    feed: FloatArray,
    limits: PlanLimits,
    calibration: CalibratedKinematics | None,
    previous: Motion,
    changed: NDArray[np.bool_],
) -> Motion:
    """A section verified again after a re-plan: only its ``changed`` samples evaluated.

    The other samples keep ``previous``'s values, which the new plan leaves as
    they were (:func:`changed_samples`); the times are the new plan's everywhere.
    The same motion as :func:`check_sections` of the new plan. ``previous`` is
    given up: its arrays are updated in place (no copy of the whole fine grid's
    motion per re-plan), but for the slider positions, which a re-plan leaves
    as they are (the path forms' own, without a calibration).
    """
    t, sd, sdd, _ = law.at_lengths(fine.s)
    idx = np.flatnonzero(changed)
    sub = Samples(*(getattr(fine, n)[idx] for n in ("s", "p", "dp", "ddp", "piece")))
    sub_forms = PathForms(*(getattr(forms, n)[idx] for n in ("q", "dq", "ddq", "a", "b", "c")))
    part = evaluate_forms(
        sub_forms, sub, t[idx], sd[idx], sdd[idx], feed[idx], limits, calibration=calibration
    )

    def spliced(old: FloatArray, new: FloatArray | float) -> FloatArray:
        old[idx] = new
        return old

    names = ("qd", "qdd", "forces")
    arrays = {n: spliced(getattr(previous, n), getattr(part, n)) for n in names}
    arrays["q"] = previous.q if calibration is None else spliced(previous.q.copy(), part.q)
    torque = speed = None
    if previous.torque is not None and part.torque is not None:
        torque = spliced(previous.torque, part.torque)
    if previous.speed is not None and part.speed is not None:
        speed = spliced(previous.speed, part.speed)
    # a limit absent from the part (the feed, with no feed there) is unused there
    uses = {n: spliced(u, part.uses.get(n, 0.0)) for n, u in previous.uses.items()}
    return Motion(t, fine.s, sd, sdd, fine.p, **arrays, torque=torque, speed=speed, uses=uses)


def _cut(m: Motion, idx: slice) -> Motion:
    """The samples ``idx`` of a motion."""
    pick = {
        n: getattr(m, n)[idx] for n in ("t", "s", "sd", "sdd", "p", "q", "qd", "qdd", "forces")
    }
    return Motion(
        **pick,
        torque=None if m.torque is None else m.torque[idx],
        speed=None if m.speed is None else m.speed[idx],
        uses={k: v[idx] for k, v in m.uses.items()},
        qddd=None if m.qddd is None else m.qddd[idx],
    )
