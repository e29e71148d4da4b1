"""Shared fixtures: an isolated URDF cache and the prototype's models."""

from __future__ import annotations

import math
import os
from collections.abc import Iterator

import numpy as np
import pytest

import orthoglide_pin as og

#: Prototype leg length [m] (paper, section 4).
PROTOTYPE_LEG = 0.31
#: Prototype cube: lower corner coordinate on each axis [m] and side [m].
CUBE_CORNER = -PROTOTYPE_LEG / math.sqrt(18.0)
CUBE_SIDE = 0.2


@pytest.fixture(scope="session", autouse=True)
def _isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Keep every rendered URDF out of the user's cache."""
    old = os.environ.get(og.description.CACHE_ENV)
    os.environ[og.description.CACHE_ENV] = str(tmp_path_factory.mktemp("urdf-cache"))
    yield
    if old is None:
        os.environ.pop(og.description.CACHE_ENV, None)
    else:
        os.environ[og.description.CACHE_ENV] = old


@pytest.fixture(scope="session")
def params() -> og.OrthoglideParams:
    return og.prototype()


@pytest.fixture(scope="session")
def model(params: og.OrthoglideParams) -> og.ClosedLoopModel:
    return og.ClosedLoopModel(params)


def cube_points(n: int, seed: int) -> np.ndarray:
    """``n`` seeded random points in the prototype cube [m], shape (n, 3)."""
    rng = np.random.default_rng(seed)
    return CUBE_CORNER + CUBE_SIDE * rng.random((n, 3))
