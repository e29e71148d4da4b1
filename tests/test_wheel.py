"""The built wheel ships the description and renders it from a fresh environment."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = (
    "orthoglide_pin/_description/orthoglide.urdf.xacro",
    "orthoglide_pin/_description/orthoglide_leg.xacro",
    "orthoglide_pin/_description/orthoglide_loops.yaml",
    "orthoglide_pin/_description/urdf/orthoglide_prototype.urdf",
    "orthoglide_pin/_description/urdf/orthoglide_prototype.loops.yaml",
    "orthoglide_pin/drives/examples/prototype_drive.yaml",
    "orthoglide_pin/py.typed",
)

pytestmark = pytest.mark.slow


def _run(*args: str | Path, cwd: Path) -> str:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # only the wheel
    done = subprocess.run(
        [str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    src = tmp_path_factory.mktemp("src")
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    for name in ("orthoglide_pin", "description"):
        shutil.copytree(ROOT / name, src / name, ignore=ignore)
    out = tmp_path_factory.mktemp("dist")
    _run(
        sys.executable,
        "-m",
        "pip",
        "wheel",
        "--no-deps",
        "--no-build-isolation",
        "--no-index",
        "-w",
        out,
        ".",
        cwd=src,
    )
    (whl,) = out.glob("orthoglide_pin-*.whl")
    return whl


def test_wheel_ships_the_description(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    missing = [n for n in SHIPPED if n not in names]
    assert not missing


def test_wheel_ships_every_subpackage(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    source = ROOT / "orthoglide_pin"
    for init in source.rglob("__init__.py"):
        relative = init.relative_to(ROOT).as_posix()
        assert relative in names
        for module in init.parent.glob("*.py"):
            assert module.relative_to(ROOT).as_posix() in names


def test_fresh_environment_renders_the_urdf(wheel: Path, tmp_path: Path) -> None:
    env_dir = tmp_path / "fresh"
    _run(sys.executable, "-m", "venv", "--without-pip", env_dir, cwd=tmp_path)
    python = env_dir / "bin" / "python"
    _run(
        sys.executable,
        "-m",
        "pip",
        "--python",
        python,
        "install",
        "--no-deps",
        "--no-index",
        wheel,
        cwd=tmp_path,
    )
    # The dependencies (numpy, pin, xacro, PyYAML) come from this environment, added as a
    # site directory *after* the fresh one, so the package itself comes from the wheel.
    purelib = Path(sysconfig.get_paths()["purelib"])
    fresh_purelib = next((env_dir / "lib").glob("python3*/site-packages"))
    # An editable install of the package in this environment must not leak in: drop its finders.
    (fresh_purelib / "zz_dependencies.pth").write_text(
        f"import site, sys; site.addsitedir({str(purelib)!r}); "
        "sys.meta_path[:] = [f for f in sys.meta_path "
        "if not getattr(f, '__module__', '').startswith('__editable__')]; "
        "sys.path_hooks[:] = [h for h in sys.path_hooks "
        "if not getattr(h, '__module__', '').startswith('__editable__')]\n"
    )
    script = (
        "import orthoglide_pin as og, orthoglide_pin.cli, pinocchio as pin\n"
        "print(og.__file__)\n"
        "print(orthoglide_pin.cli.__file__)\n"
        "print(og.machine.description.xacro_path())\n"
        "text = og.render_urdf(og.prototype(), use_cache=False)\n"
        "print(pin.buildModelFromXML(text).nq)\n"
        "print(text == og.prototype_urdf_path().read_text())\n"
    )
    lines = _run(python, "-c", script, cwd=tmp_path).split()
    assert all(line.startswith(str(env_dir)) for line in lines[:3])
    assert lines[3:] == ["18", "True"]
    urdf = tmp_path / "m.urdf"
    _run(env_dir / "bin" / "orthoglide", "urdf", "-o", urdf, cwd=tmp_path)
    assert "leg3_bar_b_tip" in urdf.read_text()
    assert "leg3_bar_b_tip" in (tmp_path / "m.loops.yaml").read_text()
    example = _run(env_dir / "bin" / "orthoglide", "drive", "--example", cwd=tmp_path)
    assert "rotor_inertia" in example and "motor:" in example
