"""A plan's sections evaluated in one batch: path forms, planning grids, verification.

A program's sections are sampled once on the fine (verification) grid; the
planning grid is every ``REFINE``-th sample of it (:func:`coarse_samples`,
:func:`coarse_forms`). The path forms of the closed-loop dynamics
(:func:`~orthoglide_pin.dynamics.path_forms.path_forms`) of all sections are
computed in one batch (:func:`section_forms`), and so is the verification of
their time laws on the fine grid (:func:`check_sections`, through
:func:`~orthoglide_pin.planning.verify.evaluate_forms`), cut back into one
motion per section. :func:`~orthoglide_pin.planning.plan.plan_program` drives
them.
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.dynamics.path_forms import PathForms, path_forms
from orthoglide_pin.planning.calibrated import CalibratedKinematics
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.parametrize import SectionPlan
from orthoglide_pin.planning.path import Samples
from orthoglide_pin.planning.verify import REFINE, Motion, evaluate_forms

FloatArray = NDArray[np.float64]


def section_forms(
    dyn: ClosedLoopDynamics, grids: list[Samples], g: FloatArray, w: FloatArray | None
) -> list[PathForms]:
    """The path forms of every section, from one batch."""
    if not grids:
        return []
    cat = [np.concatenate([getattr(x, name) for x in grids]) for name in ("p", "dp", "ddp")]
    forms = path_forms(dyn, *cat, gravity=g, wrench=w)
    cuts = np.cumsum([x.s.size for x in grids])[:-1]
    fields = ("q", "dq", "ddq", "a", "b", "c")
    split = {name: np.split(getattr(forms, name), cuts) for name in fields}
    return [PathForms(**{name: split[name][k] for name in fields}) for k in range(len(grids))]


def coarse_samples(fine: Samples) -> Samples:
    """The planning grid of a section from its fine grid (every ``REFINE``-th sample)."""
    return Samples(*(getattr(fine, n)[::REFINE] for n in ("s", "p", "dp", "ddp", "piece")))


def coarse_forms(forms: PathForms) -> PathForms:
    """The path forms at the planning grid from those at the fine grid."""
    return PathForms(*(getattr(forms, n)[::REFINE] for n in ("q", "dq", "ddq", "a", "b", "c")))


def check_sections(
    forms: list[PathForms],
    fines: list[Samples],
    laws: list[SectionPlan | None],
    feeds: list[FloatArray],
    limits: PlanLimits,
    calibration: CalibratedKinematics | None = None,
) -> list[Motion]:
    """Each section verified on its fine grid, from the path forms there, in one batch."""
    timed = []
    for fine, law in zip(fines, laws, strict=True):
        assert law is not None
        timed.append(law.at_lengths(fine.s)[:3])

    def joined(parts: list[FloatArray]) -> FloatArray:
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    s, p, dp, ddp = (joined([getattr(f, n) for f in fines]) for n in ("s", "p", "dp", "ddp"))
    samples = Samples(s, p, dp, ddp, np.concatenate([f.piece for f in fines]))
    cat = PathForms(
        *(joined([getattr(f, n) for f in forms]) for n in ("q", "dq", "ddq", "a", "b", "c"))
    )
    t, sd, sdd = (joined([x[j] for x in timed]) for j in range(3))
    motion = evaluate_forms(
        cat, samples, t, sd, sdd, joined(feeds), limits, calibration=calibration
    )
    if len(fines) == 1:
        return [motion]
    ends = np.cumsum([0] + [f.s.size for f in fines])
    return [_cut(motion, slice(a, b)) for a, b in itertools.pairwise(ends.tolist())]


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
