"""Sampled tool trajectories: segments chained, with optional dwells, at a fixed period.

:func:`build_trajectory` concatenates segments of :mod:`orthoglide_pin.motion.segments`
(optionally with a rest between consecutive ones), checks that each starts
where the previous one ends, and samples them at ``t_k = k dt``,
``k = 0 .. ceil(T / dt)``, so the last sample is the rest state at the end (at
``T`` or up to ``dt`` after it). The result, a :class:`Trajectory`, holds the
tool's positions, velocities, accelerations and jerks in the world frame (SI
units), and the segment of each sample.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin._validation import bounded_number, positive_number
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.motion.segments import Dwell, Segment

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.intp]

#: Default sampling period [s] (1 kHz, a common servo rate).
DEFAULT_DT: Final[float] = 1e-3
#: Largest gap allowed between the end of a segment and the start of the next [m].
CONTINUITY_TOL: Final[float] = 1e-9
#: Largest number of samples :func:`build_trajectory` produces, checked before
#: anything is allocated (each sample holds 14 floats: 5 M samples are 0.56 GB).
MAX_SAMPLES: Final[int] = 5_000_000


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A sampled tool trajectory, world frame, SI units.

    Attributes:
        t: Sample times ``k dt`` [s], shape (N,).
        p: Tool positions [m], shape (N, 3).
        v: Tool velocities [m/s], shape (N, 3).
        a: Tool accelerations [m/s^2], shape (N, 3).
        j: Tool jerks [m/s^3], shape (N, 3).
        segment: Index of each sample's segment in ``labels``, shape (N,).
        labels: Name of each segment, in order.
        segment_times: Start time of each segment and the end time ``T`` [s],
            shape (K + 1,).
        dt: Sampling period [s].
    """

    t: FloatArray
    p: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    segment: IntArray
    labels: tuple[str, ...]
    segment_times: FloatArray
    dt: float = field(default=DEFAULT_DT)

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def duration(self) -> float:
        """End time ``T`` of the last segment [s]."""
        return float(self.segment_times[-1])

    @property
    def speed(self) -> FloatArray:
        """Tool speed ``|v|`` [m/s], shape (N,)."""
        out: FloatArray = np.linalg.norm(self.v, axis=1)
        return out

    def where(self, label: str) -> NDArray[np.bool_]:
        """Mask of the samples of the segments named ``label``, shape (N,).

        Raises:
            InvalidParameterError: No segment has that name.
        """
        if not isinstance(label, str):
            raise InvalidParameterError("label", label, "one of " + ", ".join(self.labels))
        ids = [k for k, name in enumerate(self.labels) if name == label]
        if not ids:
            raise InvalidParameterError("label", label, "one of " + ", ".join(self.labels))
        return np.isin(self.segment, ids)


def build_trajectory(
    segments: Sequence[Segment], *, dt: float = DEFAULT_DT, dwell_time: float = 0.0
) -> Trajectory:
    """Concatenate segments and sample them uniformly.

    Args:
        segments: Segments in order; each must start where the previous one
            ends (within ``CONTINUITY_TOL``).
        dt: Sampling period [s], positive.
        dwell_time: Rest inserted between consecutive segments [s]
            (non-negative; such rests are labelled ``"dwell"``).

    Returns:
        The sampled trajectory.

    Raises:
        InvalidParameterError: No segment, a gap between segments, a bad
            ``dt`` or ``dwell_time``, or more than ``MAX_SAMPLES`` samples.
    """
    step = positive_number("dt", dt, "a positive finite sampling period [s]")
    rest = bounded_number("dwell_time", dwell_time, math.inf, "[s]", allow_zero=True)
    given: object = segments  # any object may come through the API
    if isinstance(given, (str, bytes)) or not hasattr(given, "__len__"):
        raise InvalidParameterError("segments", segments, "a sequence of segments")
    if len(segments) == 0:
        raise InvalidParameterError("segments", segments, "at least one segment")
    for k, seg in enumerate(segments):
        if not all(hasattr(seg, attr) for attr in ("duration", "start", "end", "evaluate")):
            allowed = "a segment (line_move, circle_move, dwell, ...)"
            raise InvalidParameterError(f"segments[{k}]", seg, allowed)
    chain: list[Segment] = []
    for k, seg in enumerate(segments):
        if chain:
            gap = float(np.linalg.norm(seg.start - chain[-1].end))
            if not gap <= CONTINUITY_TOL:
                allowed = f"a start within {CONTINUITY_TOL:g} m of the end of the previous segment"
                raise InvalidParameterError(f"segments[{k}].start", tuple(seg.start), allowed)
            if rest > 0.0:
                chain.append(Dwell(chain[-1].end, rest))
        chain.append(seg)
    times = np.concatenate(([0.0], np.cumsum([seg.duration for seg in chain])))
    total = float(times[-1])
    ratio = total / step  # inf for a subnormal step
    if not ratio < MAX_SAMPLES:
        given = total - rest * (len(chain) - len(segments))  # without the inserted rests
        blame_rest = rest > 0.0 and given / step < MAX_SAMPLES
        name, value = ("dwell_time", dwell_time) if blame_rest else ("dt", dt)
        raise InvalidParameterError(
            name, value, f"at most {MAX_SAMPLES} samples ({total:.6g} s at dt = {step:g} s)"
        )
    count = math.ceil(ratio - 1e-9) + 1
    t = np.arange(count, dtype=np.float64) * step
    index = np.minimum(np.searchsorted(times[1:], t, side="right"), len(chain) - 1)
    bounds = np.searchsorted(index, np.arange(len(chain) + 1))
    p, v, a, j = (np.empty((count, 3)) for _ in range(4))
    for k, seg in enumerate(chain):  # samples of a segment are contiguous
        sl = slice(int(bounds[k]), int(bounds[k + 1]))
        if sl.start < sl.stop:
            p[sl], v[sl], a[sl], j[sl] = seg.evaluate(t[sl] - times[k])
    return Trajectory(t, p, v, a, j, index, tuple(s.label for s in chain), times, step)
