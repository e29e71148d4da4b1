"""The built wheel, and fresh environments that install it (shared by the wheel tests).

A fresh environment holds the wheel only; its dependencies come from this
environment, added as a site directory *after* the fresh one, so the package
itself is the wheel's. An editable install of the package in this environment
must not leak in: its import finders are dropped.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: A subprocess of these tests never takes longer [s].
TIMEOUT = 600


def run(*args: str | Path, cwd: Path) -> str:
    """Run a command without PYTHONPATH (only the wheel), assert success, return stdout."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    done = subprocess.run(
        [str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def build_wheel(src: Path, out: Path) -> Path:
    """Build the project's wheel from a copy of its sources in ``src`` into ``out``."""
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc")
    for name in ("orthoglide_pin", "description"):
        shutil.copytree(ROOT / name, src / name, ignore=ignore)
    run(
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


def fresh_environment(wheel: Path, env_dir: Path) -> Path:
    """A new environment at ``env_dir`` with ``wheel`` installed; returns its python.

    Returns:
        The environment's interpreter. Its ``site-packages`` is
        ``site_packages(python)``, where a test may add ``.pth`` files.
    """
    run(sys.executable, "-m", "venv", "--without-pip", env_dir, cwd=env_dir.parent)
    python = env_dir / "bin" / "python"
    run(
        sys.executable,
        "-m",
        "pip",
        "--python",
        python,
        "install",
        "--no-deps",
        "--no-index",
        wheel,
        cwd=env_dir.parent,
    )
    purelib = Path(sysconfig.get_paths()["purelib"])
    (site_packages(python) / "zz_dependencies.pth").write_text(
        f"import site, sys; site.addsitedir({str(purelib)!r}); "
        "sys.meta_path[:] = [f for f in sys.meta_path "
        "if not getattr(f, '__module__', '').startswith('__editable__')]; "
        "sys.path_hooks[:] = [h for h in sys.path_hooks "
        "if not getattr(h, '__module__', '').startswith('__editable__')]\n"
    )
    return python


def site_packages(python: Path) -> Path:
    """The ``site-packages`` folder of the environment of ``python``."""
    return next((python.parents[1] / "lib").glob("python3*/site-packages"))
