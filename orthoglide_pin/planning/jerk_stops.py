"""Where a jerk-limited plan stops the tool: curvature steps and tight blends.

The slider jerk of a motion at speed through a step of the curvature is
infinite: the acceleration ``ddq s'^2`` steps. Under ``G64`` the path's
curvature is continuous (corners and tangent joints are blended by G2
quintics, :mod:`~orthoglide_pin.planning.blend`) except at a tangent joint
whose blend cannot be made; with a jerk limit the tool stops there:
:func:`split_at_curvature_steps` ends a section at each such junction. A
blend of a small tolerance has a large third derivative ``dddp``: the jerk
at constant speed, ``dddq s'^3``, caps its speed near
``(J / |dddp|)^(1/3)``, a crawl (4 mm/s through the shipped contour's
corners at 500 m/s^3). The moving average of the re-timing
(:mod:`~orthoglide_pin.planning.jerk`) would spread that crawl over the
section, so the tool stops at both ends of such a blend instead
(:func:`tight_blend`).
"""

from __future__ import annotations

from typing import Final

import numpy as np

from orthoglide_pin.planning.geometry import Piece
from orthoglide_pin.planning.path import CURVATURE_RTOL, Path, Section

#: Junctions whose curvature vectors differ by more than this stop the tool [1/m].
CURVATURE_STEP_TOL: Final[float] = 1e-6
#: A blend whose jerk caps its speed below this share of its feed is passed from rest [-].
BLEND_STOP_SHARE: Final[float] = 0.3
#: Points where a blend's third derivative is probed.
BLEND_PROBES: Final[int] = 17


def split_at_curvature_steps(
    path: Path, jerk: float | None = None, speed: float | None = None
) -> tuple[Path, int]:
    """The path with a stop wherever the curvature vector steps, and the stops added.

    Args:
        path: The path (:func:`~orthoglide_pin.planning.path.build_path`).
        jerk: The slider jerk limit [m/s^3]: a corner blend that the jerk limits to a
            crawl is passed from rest to rest (see :func:`tight_blend`); ``None``: not.
        speed: The slider speed limit [m/s] (the speed a rapid blend is compared to).

    Returns:
        The path whose sections end at every junction where ``p''`` changes by
        more than :data:`CURVATURE_STEP_TOL` and than the share
        :data:`~orthoglide_pin.planning.path.CURVATURE_RTOL` of its size (the
        joints :func:`~orthoglide_pin.planning.path.build_path` leaves unblended:
        under ``G64`` only a tangent joint whose blend cannot be made) and at
        both ends of a tight blend, and how many stops that adds.
    """
    out: list[Section] = []
    stops = 0
    for sec in path.sections:
        n = len(sec.pieces)
        cut = [False] * n  # cut[k]: a stop between pieces k - 1 and k
        for k in range(1, n):
            a, b = sec.pieces[k - 1], sec.pieces[k]
            end = a.evaluate(np.array([a.length]))[2][0]
            start = b.evaluate(np.array([0.0]))[2][0]
            step = float(np.linalg.norm(end - start))
            size = max(float(np.linalg.norm(end)), float(np.linalg.norm(start)))
            cut[k] = step > max(CURVATURE_STEP_TOL, CURVATURE_RTOL * size)
        if jerk is not None:
            for k, piece in enumerate(sec.pieces):
                if piece.is_blend and tight_blend(piece, jerk, speed):
                    cut[k] = cut[k] or k > 0
                    if k + 1 < n:
                        cut[k + 1] = True
        runs: list[list[int]] = [[0]] if n else []
        for k in range(1, n):
            if cut[k]:
                runs.append([k])
                stops += 1
            else:
                runs[-1].append(k)
        if len(runs) <= 1:
            out.append(sec)
            continue
        for j, run in enumerate(runs):
            last = j == len(runs) - 1
            pieces = tuple(sec.pieces[k] for k in run)
            offsets = np.concatenate([[0.0], np.cumsum([p.length for p in pieces])])
            out.append(
                Section(
                    pieces, offsets, sec.dwell if last else 0.0, sec.dwell_block if last else -1
                )
            )
    return Path(path.program, tuple(out)), stops


def tight_blend(piece: Piece, jerk: float, speed: float | None) -> bool:
    """Whether the jerk at constant speed caps a blend's speed below a share of its feed.

    The cap is ``(J / max |dddp|)^(1/3)`` [m/s], ``dddp`` the path's third
    derivative (:meth:`~orthoglide_pin.planning.geometry.Piece.third`) on
    :data:`BLEND_PROBES` points; the feed is the blend's (on a rapid move the
    slider speed limit ``speed``, or any speed). Below :data:`BLEND_STOP_SHARE`
    of it, a stop at each end costs less than a crawl spread over the section.
    """
    third = float(np.abs(piece.third(np.linspace(0.0, piece.length, BLEND_PROBES))).max())
    if third <= 0.0:
        return False
    feed = piece.feed if piece.feed is not None else speed
    return feed is None or float(np.cbrt(jerk / third)) < BLEND_STOP_SHARE * feed
