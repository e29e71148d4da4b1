"""The notebooks run headless, top to bottom, on a kernel of this environment.

They are executed once per test run (``tests/_notebooks.py``: nbclient, a fresh
ipykernel of the running interpreter, IPC sockets, no notebook server or
network port); the documentation tests render the same executed copies. They
are committed without outputs. Executed, each shows its meshcat scene as
static HTML (an iframe with the page inlined) and its figures as PNG images,
never as the text ``<Figure size ...>`` of a figure Jupyter could not display.

The tests then read what a notebook printed and check it against the commands
(through the API): the prototype's factors (01), the report's verdict on the
shipped drive (03), the design method's exact leg (04), the calibration (06).
They import nothing but the documented install (``pip install '.[all]'``):
never the test suite.
"""

from __future__ import annotations

import ast
import itertools
import re
import sys

import numpy as np
import pytest
from _notebooks import NOTEBOOKS, NotebookRuns

import orthoglide_pin as og
from orthoglide_pin._lazy import EXTRAS

nbformat = pytest.importorskip("nbformat")
EXPECTED = (
    "01_kinematics_isotropy.ipynb",
    "02_design.ipynb",
    "03_torque_requirements.ipynb",
    "04_leg_length_sweep.ipynb",
    "05_stiffness.ipynb",
    "06_calibration.ipynb",
    "07_vibration.ipynb",
    "08_part_accuracy.ipynb",
)
#: The static viewer inlines meshcat's three.js bundle (~0.9 MB).
MIN_SCENE_CHARS = 500_000
#: Figures each notebook shows: slice maps (1), the design against its bounds
#: (2), worst-case maps and the cycle (3), the sweep's trade-offs, a program's
#: cycle time against the leg and its contour error in MuJoCo for two legs (4),
#: stiffness maps and the effect of leg length and bar section (5), the error
#: before and after calibration, its dependence on the poses, the sensitivity
#: maps (6), the lowest frequency on a slice and against the leg length (7), the
#: lobes at home and Q2, the surface error and margins along the pocket and the
#: sweep's accuracy columns (8).
EXPECTED_IMAGES = {
    "01_kinematics_isotropy.ipynb": 2,
    "02_design.ipynb": 1,
    "03_torque_requirements.ipynb": 2,
    "04_leg_length_sweep.ipynb": 3,
    "05_stiffness.ipynb": 2,
    "06_calibration.ipynb": 3,
    "07_vibration.ipynb": 2,
    "08_part_accuracy.ipynb": 3,
}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
#: Least size of a real figure [bytes] (a blank 1-pixel PNG is ~70).
MIN_PNG_BYTES = 10_000
#: What a figure shows as text, with or without its class name (``<Figure size ...>``).
FIGURE_TEXT = "Figure size"
#: Modules a notebook may import besides the standard library: the package, its
#: core dependencies that notebooks use, IPython (the kernel's) and every extra
#: of ``[all]``.
DOCUMENTED_MODULES = frozenset(
    {"orthoglide_pin", "IPython", "numpy", "matplotlib"}
    | {m for modules in EXTRAS.values() for m in modules}
)
#: The paper's bounds on the transmission factors and its 200 mm cube.
PAPER_BOUNDS = (0.5, 2.0)
PAPER_SIDE = 0.2


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


def _printed(book: object) -> list[str]:
    """Every line the notebook printed (stream outputs)."""
    out = []
    for output in _outputs(book):
        if output.get("output_type") == "stream":
            out += _text(output.get("text", "")).splitlines()
    return out


def _line(book: object, start: str) -> str:
    """The one printed line that starts with ``start``."""
    lines = [line for line in _printed(book) if line.startswith(start)]
    assert len(lines) == 1, (start, _printed(book))
    return lines[0]


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


@pytest.mark.parametrize("name", EXPECTED)
def test_notebooks_need_only_the_documented_install(name: str) -> None:
    """``pip install '.[all]'`` runs them: no module from the test suite, no path hacks."""
    book = nbformat.read(NOTEBOOKS / name, as_version=4)
    for cell in book.cells:
        if cell.cell_type != "code":
            continue
        assert "sys.path" not in cell.source, cell.source
        for node in ast.walk(ast.parse(cell.source)):
            if isinstance(node, ast.Import):
                tops = [alias.name.split(".")[0] for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                tops = [(node.module or "").split(".")[0]]
            else:
                continue
            for top in tops:
                assert top in sys.stdlib_module_names or top in DOCUMENTED_MODULES, (name, top)


def test_notebook_01_states_the_prototypes_true_factors(notebook_runs: NotebookRuns) -> None:
    book = notebook_runs.get("01_kinematics_isotropy.ipynb").book
    params = og.prototype()
    cube = params.workspace
    # Independent route: LAPACK's singular values at the cube's corners (the
    # factors' extremes over the cube are at its corners, Q2 here).
    corners = np.array(
        [cube.q1 + cube.side * np.array(c) for c in itertools.product((0, 1), repeat=3)]
    )
    sigma = np.linalg.svd(og.jacobian(corners, params.leg_length), compute_uv=False)
    lo, hi = float(sigma.min()), float(sigma.max())
    assert (f"{lo:.4f}", f"{hi:.4f}") == ("0.4989", "2.0090")  # the paper's rounding shows
    line = _line(book, "the prototype's factors over its 200 mm cube:")
    assert line.endswith(f": [{lo:.4f}, {hi:.4f}]")
    exact = og.design_from_workspace(PAPER_SIDE, *PAPER_BOUNDS).leg_length
    line = _line(book, "legs for factors in [0.5, 2] over a 200 mm cube:")
    assert f": {1e3 * exact:.2f} mm (the paper rounded them to 310 mm)" in line
    proven = _line(book, "proven over the whole cube:")
    low, high = (float(v) for v in re.findall(r"within \[([0-9.]+), ([0-9.]+)\]", proven)[0])
    assert low <= lo and high >= hi and proven.endswith("against [0.5, 2]: violated")


def test_notebook_03_verdict_is_the_reports(notebook_runs: NotebookRuns) -> None:
    """The notebook's own criterion gives ``orthoglide report --motor``'s verdict on the drive."""
    book = notebook_runs.get("03_torque_requirements.ipynb").book
    drive = og.load_drive(og.example_drive_file())  # orthoglide drive --example
    report = og.assemble_report(og.prototype(), drive)
    margins = [row.margin for row in report.verdict if row.margin is not None]
    verdict = "PASS" if report.passed else "FAIL"
    expected = f"verdict on the shipped example drive: {verdict}, least margin {min(margins):+.4f}"
    assert _line(book, "verdict on the shipped example drive:") == expected
    assert drive.motor is not None
    assert _line(book, "motor: ").startswith(f"motor: {drive.motor.name};")


def test_notebook_04_states_the_exact_leg_beside_the_grid(notebook_runs: NotebookRuns) -> None:
    book = notebook_runs.get("04_leg_length_sweep.ipynb").book
    exact = og.design_from_workspace(PAPER_SIDE, *PAPER_BOUNDS).leg_length
    line = _line(book, "exact leg of the design method for [0.5, 2]:")
    assert line.endswith(f": {1e3 * exact:.2f} mm")
    grid = _line(book, "shortest leg of the grid keeping the factors in [0.5, 2]:")
    found = re.findall(r": (\d+) mm \(grid step (\d+) mm\)", grid)
    leg, step = (1e-3 * float(v) for v in found[0])
    cube = og.prototype().workspace
    # The grid's answer: its first leg certified for the fixed cube, the one before not.
    assert og.certify_cube(leg, cube.q1, cube.side, *PAPER_BOUNDS).certified
    assert og.certify_cube(leg - step, cube.q1, cube.side, *PAPER_BOUNDS).status == "violated"
    fixed = _line(book, "shortest leg certified for this fixed cube:")
    threshold = 1e-3 * float(re.findall(r": ([0-9.]+) mm", fixed)[0])
    assert leg - step < threshold <= leg
    assert og.certify_cube(threshold + 1e-5, cube.q1, cube.side, *PAPER_BOUNDS).certified
    assert not og.certify_cube(threshold - 2e-5, cube.q1, cube.side, *PAPER_BOUNDS).certified


def test_notebook_06_calibrates_to_the_noise_level(notebook_runs: NotebookRuns) -> None:
    book = notebook_runs.get("06_calibration.ipynb").book
    assert _line(book, "outliers found:") == "outliers found: 2 of 60 poses, rows [11, 47]"
    assert _line(book, "parameters within 3 standard deviations").endswith(": 18 of 18")
    before = float(re.findall(r"RMS ([0-9.]+) um", _line(book, "uncalibrated:"))[0])
    after = float(re.findall(r"RMS ([0-9.]+) um", _line(book, "calibrated: RMS"))[0])
    assert 100 < before < 1000 and after < 5.0  # 0.1 to 0.5 mm, then a few um
    home = _line(book, "carriage position:")
    assert home.startswith(f"carriage position: {np.sqrt(3):.4f} at home")


def test_notebook_04_times_the_shipped_pocket_on_each_leg(notebook_runs: NotebookRuns) -> None:
    """The sweep's cycle time of the prototype's leg is the plan of the prototype."""
    pytest.importorskip("toppra")
    from orthoglide_pin.planning import PlanLimits, example_program_text, plan_program
    from orthoglide_pin.planning.gcode import read_program

    book = notebook_runs.get("04_leg_length_sweep.ipynb").book
    line = _line(book, "cycle time of the pocket, as shipped")
    found = dict(re.findall(r"(\d+) mm: ([0-9.]+) s", line))
    assert sorted(found) == ["270", "310", "350", "390", "430"]
    plan = plan_program(
        read_program(example_program_text("pocket")), og.prototype(), PlanLimits(1.2, 20.0)
    )
    assert float(found["310"]) == pytest.approx(plan.cycle_time, abs=5e-5)
    faster = _line(book, "cycle time of the pocket, feeds x 10")
    times = [float(t) for t in re.findall(r"mm: ([0-9.]+) s", faster)]
    assert len(times) == 5 and max(times) < 0.6 * min(float(t) for t in found.values())


def test_notebook_04_simulates_a_program_on_two_legs(notebook_runs: NotebookRuns) -> None:
    """The contour error printed is under a micrometre; the cycle is the plan's."""
    pytest.importorskip("toppra")
    pytest.importorskip("mujoco")
    book = notebook_runs.get("04_leg_length_sweep.ipynb").book
    found = re.findall(
        r"L = (\d+) mm: cycle ([0-9.]+) s, contour error ([0-9.]+) um on the feed moves",
        _line(book, "L = 360 mm: cycle"),
    )
    assert [f[0] for f in found] == ["360"]
    first = re.findall(
        r"L = 310 mm: cycle ([0-9.]+) s, contour error ([0-9.]+) um",
        _line(book, "L = 310 mm: cycle"),
    )
    assert len(first) == 1
    assert float(first[0][1]) < 1.0 and float(found[0][2]) < 1.0
    drive = og.load_drive(str(og.example_drive_file()))
    short = "G21 G90 G17\nG1 X10 Y5 Z-5 F3000\nG2 X10 Y5 I-5 J0\nG0 X0 Y0 Z0\nM30\n"
    plan = og.plan_program(og.read_program(short), og.prototype(), og.PlanLimits(drive=drive))
    assert float(first[0][0]) == pytest.approx(plan.cycle_time, abs=5e-4)


def test_notebook_08_lobes_are_the_apis_and_the_choice_holds(
    notebook_runs: NotebookRuns,
) -> None:
    """The lobes printed at home and Q2 are og.stability_lobes'; the chosen pass is stable."""
    pytest.importorskip("toppra")
    book = notebook_runs.get("08_part_accuracy.ipynb").book
    params = og.prototype()
    cut = og.read_cut_file(og.shipped_cut_file())
    speed = float(cut.spindle_speed or 0.0)
    for name, point in (("home", np.zeros(3)), ("Q2", params.workspace.q2)):
        lobes = og.stability_lobes(cut, point, params=params, zero_order=False)
        line = _line(book, f"{name}: lowest mode")
        assert line.startswith(
            f"{name}: lowest mode {lobes.model.frequencies[0]:.1f} Hz, lowest limit "
            f"{1e3 * lobes.minimum:.3f} mm, at 12000 rpm {1e3 * lobes.limit_at(speed):.3f} mm"
        )
    chosen = _line(book, "chosen leg:")
    leg = re.findall(r"chosen leg: (\d+) mm", chosen)[0]
    check = _line(book, f"L = {leg} mm, ")
    found = re.findall(r"least margin ([0-9.]+), 0 of (\d+) lines chatter", check)
    assert found and float(found[0][0]) > 1.0 and int(found[0][1]) > 0
