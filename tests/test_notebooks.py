"""The notebooks run headless, top to bottom, on a kernel of this environment.

They are executed once per test run (``tests/_notebooks.py``: nbclient, a fresh
ipykernel of the running interpreter, IPC sockets, no notebook server or
network port); the documentation tests render the same executed copies. They
are committed without outputs. Executed, each shows its meshcat scene as
static HTML (an iframe with the page inlined) and its figures as PNG images,
never as the text ``<Figure size ...>`` of a figure Jupyter could not display.
"""

from __future__ import annotations

import pytest
from _notebooks import NOTEBOOKS, NotebookRuns

nbformat = pytest.importorskip("nbformat")

EXPECTED = (
    "01_kinematics_isotropy.ipynb",
    "02_design.ipynb",
    "03_torque_requirements.ipynb",
    "04_leg_length_sweep.ipynb",
    "05_stiffness.ipynb",
)
#: The static viewer inlines meshcat's three.js bundle (~0.9 MB).
MIN_SCENE_CHARS = 500_000
#: Figures each notebook shows: slice maps (1), the design against its bounds
#: (2), worst-case maps and the cycle (3), the sweep's trade-offs (4), stiffness
#: maps and the effect of leg length and bar section (5).
EXPECTED_IMAGES = {
    "01_kinematics_isotropy.ipynb": 2,
    "02_design.ipynb": 1,
    "03_torque_requirements.ipynb": 2,
    "04_leg_length_sweep.ipynb": 1,
    "05_stiffness.ipynb": 2,
}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
#: Least size of a real figure [bytes] (a blank 1-pixel PNG is ~70).
MIN_PNG_BYTES = 10_000
#: What a figure shows as text, with or without its class name (``<Figure size ...>``).
FIGURE_TEXT = "Figure size"


def test_the_notebooks_are_there_without_outputs() -> None:
    assert tuple(sorted(p.name for p in NOTEBOOKS.glob("*.ipynb"))) == EXPECTED
    for name in EXPECTED:
        book = nbformat.read(NOTEBOOKS / name, as_version=4)
        nbformat.validate(book)
        code = [c for c in book.cells if c.cell_type == "code"]
        assert code and all(c.outputs == [] and c.execution_count is None for c in code), name
        assert any("import orthoglide_pin as og" in c.source for c in code), name


def _html(book: object) -> list[str]:
    out = []
    for cell in book.cells:  # type: ignore[attr-defined]
        for output in cell.get("outputs", []):
            html = output.get("data", {}).get("text/html")
            if html:
                out.append(html if isinstance(html, str) else "".join(html))
    return out


def _outputs(book: object) -> list[dict[str, object]]:
    return [o for c in book.cells for o in c.get("outputs", [])]  # type: ignore[attr-defined]


def _text(value: object) -> str:
    return value if isinstance(value, str) else "".join(value)  # type: ignore[arg-type]


def _images(book: object) -> list[bytes]:
    """The PNG images shown, decoded."""
    import base64

    out = []
    for output in _outputs(book):
        data = output.get("data", {})
        if "image/png" in data:  # type: ignore[operator]
            out.append(base64.b64decode(_text(data["image/png"])))  # type: ignore[index]
    return out


def _figures_as_text(book: object) -> list[str]:
    """Outputs that show a figure as its text only (no image beside it)."""
    out = []
    for output in _outputs(book):
        data = output.get("data", {})
        text = _text(output.get("text", "")) + _text(data.get("text/plain", ""))  # type: ignore[attr-defined]
        if FIGURE_TEXT in text and "image/png" not in data:  # type: ignore[operator]
            out.append(text)
    return out


@pytest.mark.parametrize("name", EXPECTED)
def test_notebook_runs_and_embeds_its_scene(name: str, notebook_runs: NotebookRuns) -> None:
    run = notebook_runs.get(name)  # raises CellExecutionError on the first failing cell
    book = run.book
    errors = [
        o for c in book.cells for o in c.get("outputs", []) if o.get("output_type") == "error"
    ]
    assert errors == []
    scenes = [h for h in _html(book) if h.startswith("<iframe srcdoc=")]
    assert len(scenes) == 1 and len(scenes[0]) > MIN_SCENE_CHARS
    assert "MeshCat.Viewer" in scenes[0] and "ogCommands" in scenes[0]
    # Figures are images, never "<Figure size ...>" text.
    images = _images(book)
    assert len(images) >= EXPECTED_IMAGES[name], f"{len(images)} images"
    assert all(i.startswith(PNG_MAGIC) and len(i) > MIN_PNG_BYTES for i in images)
    assert _figures_as_text(book) == []
    assert run.left_behind == []  # the notebooks leave nothing behind
