"""Shared by the elasticity tests: seeded points of a design's cube."""

from __future__ import annotations

import numpy as np

import orthoglide_pin as og


def cube_points(params: og.OrthoglideParams, count: int, seed: int) -> np.ndarray:
    """Q1 and Q2, then ``count - 2`` seeded uniform points of the design's cube [m], (count, 3)."""
    cube = params.workspace
    rng = np.random.default_rng(seed)
    corners = np.array([cube.q1, cube.q2])
    return np.concatenate([corners, cube.q1 + cube.side * rng.uniform(0, 1, (count - 2, 3))])
