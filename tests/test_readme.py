"""The Python examples of the README run as written."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"
JACOBIAN_TOL = 1e-9


def test_python_examples_run() -> None:
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.DOTALL)
    assert blocks
    namespace: dict[str, object] = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)
    # The tour's claims hold.
    model, assembly, og = namespace["model"], namespace["assembly"], namespace["og"]
    points, length = namespace["points"], namespace["L"]
    assert model.constraint_rank(assembly.q) == 15  # type: ignore[attr-defined]
    assert model.mobility(assembly.q) == 3  # type: ignore[attr-defined]
    expected = og.jacobian(points[1], length)  # type: ignore[attr-defined,index]
    got = model.jacobian(assembly.q)  # type: ignore[attr-defined]
    assert np.max(np.abs(got - expected)) < JACOBIAN_TOL
