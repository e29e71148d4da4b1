"""The viewer in a real browser: headless Chromium (WebGL through SwiftShader).

Each test renders a page, takes a screenshot (kept in ``artifacts/screenshots/``)
and checks what a person would see, by the hues of the pixels: the machine's
materials (bars, carriages, platform, colours read from the URDF), and the
ellipsoids' colours at both ends of their colormap; and that the machine stands
the right way up (the vertical slider's carriage above the platform).

Chromium is the Debian ``chromium`` package. Where it is missing these tests
are skipped, unless ``ORTHOGLIDE_REQUIRE_BROWSER=1`` (set by ``.ci/run``, which
installs it) turns the skip into a failure.
"""

from __future__ import annotations

import json
import os
import selectors
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.viewer import Viewer, overlays

ROOT = Path(__file__).resolve().parents[2]
#: Where the screenshots are kept (git-ignored).
SHOTS = ROOT / "artifacts" / "screenshots"
#: Executable names of Chromium.
CHROMIUM_NAMES = ("chromium", "chromium-browser")
#: Environment variable that makes a missing Chromium a failure.
REQUIRE_ENV = "ORTHOGLIDE_REQUIRE_BROWSER"
WINDOW = (1000, 750)
#: Virtual time given to a page before its screenshot [ms].
BUDGET_MS = 2500
#: Pixels of a hue needed to call a colour present, and most allowed when absent.
PRESENT_PIXELS = 300
ABSENT_PIXELS = 5
#: Hue window [turns], and least saturation and value of a counted pixel.
HUE_TOL = 0.025
MIN_SATURATION = 0.4
MIN_VALUE = 0.2
#: Share of pixels that must change between two different scenes.
MIN_CHANGED = 0.005
#: ... between two moments of a mode's swing (a few centimetres: the parts shift
#: by a few pixels; 0.4 % of the pixels change at the prototype's lowest mode).
MIN_CHANGED_MODE = 0.001
#: Least height of the carriages' centre of colour over the platform's [pixels]
#: (about 190 upright; about 0 upside down, where the vertical one hangs below).
MIN_CARRIAGES_ABOVE = 100
#: Seconds to wait for the live server's first line and for its exit.
SERVER_TIMEOUT = 60.0


@pytest.fixture(scope="module")
def chromium() -> str:
    for name in CHROMIUM_NAMES:
        path = shutil.which(name)
        if path:
            return path
    message = "chromium not found on PATH (Debian: apt-get install chromium)"
    if os.environ.get(REQUIRE_ENV) == "1":
        pytest.fail(f"{message}, and {REQUIRE_ENV}=1 requires the browser tests")
    pytest.skip(f"{message}: browser tests skipped (set {REQUIRE_ENV}=1 to fail instead)")


def screenshot(chromium: str, url: str, name: str, budget_ms: int = BUDGET_MS) -> np.ndarray:
    """Render ``url`` headless and return the screenshot's RGB, shape (H, W, 3), in [0, 1]."""
    import matplotlib.image

    SHOTS.mkdir(parents=True, exist_ok=True)
    out = SHOTS / f"{name}.png"
    out.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory() as profile:
        args = [
            chromium,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-unsafe-swiftshader",
            "--use-angle=swiftshader",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--mute-audio",
            f"--user-data-dir={profile}",
            f"--window-size={WINDOW[0]},{WINDOW[1]}",
            f"--virtual-time-budget={budget_ms}",
            f"--screenshot={out}",
            url,
        ]
        done = subprocess.run(args, capture_output=True, text=True, timeout=180)
    assert out.is_file(), f"no screenshot (exit {done.returncode}): {done.stderr[-2000:]}"
    image = np.asarray(matplotlib.image.imread(out), dtype=float)[..., :3]
    assert image.shape[:2] == (WINDOW[1], WINDOW[0])
    return image


def hue_mask(image: np.ndarray, rgb: tuple[float, ...] | np.ndarray) -> np.ndarray:
    """The saturated pixels whose hue is that of ``rgb`` (shading keeps the hue), (H, W)."""
    from matplotlib.colors import rgb_to_hsv

    hsv = rgb_to_hsv(image)
    hue = float(rgb_to_hsv(np.asarray(rgb, dtype=float)[:3])[0])
    distance = np.abs((hsv[..., 0] - hue + 0.5) % 1.0 - 0.5)
    mask: np.ndarray = (
        (distance < HUE_TOL) & (hsv[..., 1] > MIN_SATURATION) & (hsv[..., 2] > MIN_VALUE)
    )
    return mask


def count_hue(image: np.ndarray, rgb: tuple[float, ...] | np.ndarray) -> int:
    """Number of saturated pixels whose hue is that of ``rgb``."""
    return int(hue_mask(image, rgb).sum())


def mean_row(image: np.ndarray, rgb: tuple[float, ...] | np.ndarray) -> float:
    """Mean row (0 at the top of the image) of the pixels of the hue of ``rgb``."""
    rows, _ = np.nonzero(hue_mask(image, rgb))
    return float(rows.mean())


def machine_colours(viewer: Viewer) -> dict[str, tuple[float, ...]]:
    """Material colours of a bar, a carriage and the platform, as drawn."""
    links = {"bar": "leg1_bar_a", "carriage": "leg1_carriage", "platform": "platform"}
    by_link = {v.link: v.rgba for v in viewer.drawing.visuals}
    return {name: by_link[link] for name, link in links.items()}


def ellipsoid_end_colours(viewer: Viewer) -> dict[str, np.ndarray]:
    """Colours of the best and worst conditioned ellipsoids drawn."""
    ells = viewer.ellipsoids
    assert ells is not None and viewer.scene.legend is not None
    lo, hi = viewer.scene.legend["min"], viewer.scene.legend["max"]
    ends = np.array([ells.condition.min(), ells.condition.max()])
    rgb = overlays.colors(ends, lo, hi)
    return {"best": rgb[0], "worst": rgb[1]}


def assert_machine_drawn(image: np.ndarray, viewer: Viewer) -> None:
    colours = machine_colours(viewer)
    for name, rgb in colours.items():
        assert count_hue(image, rgb) >= PRESENT_PIXELS, f"{name} colour {rgb} not seen"
    # Upright: the carriages (the vertical slider's on top) sit above the platform.
    above = mean_row(image, colours["platform"]) - mean_row(image, colours["carriage"])
    assert above > MIN_CARRIAGES_ABOVE, f"carriages only {above:.0f} px above the platform"


@pytest.fixture(scope="module")
def scenes(model: og.ClosedLoopModel) -> dict[str, Viewer]:
    plain = Viewer(model)
    plain.add_workspace()
    with_ellipsoids = Viewer(model)
    with_ellipsoids.add_workspace()
    with_ellipsoids.add_ellipsoids(with_ellipsoids.grid_points(3))
    return {"plain": plain, "ellipsoids": with_ellipsoids}


def test_static_html_shows_the_machine_and_its_ellipsoids(
    chromium: str, scenes: dict[str, Viewer], tmp_path: Path
) -> None:
    images = {}
    for name, viewer in scenes.items():
        page = viewer.save_html(tmp_path / f"{name}.html")
        images[name] = screenshot(chromium, page.as_uri(), f"static_{name}")
        assert_machine_drawn(images[name], viewer)
    colours = ellipsoid_end_colours(scenes["ellipsoids"])
    # Cyan and magenta: no material of the machine has these hues.
    for name, rgb in colours.items():
        assert count_hue(images["ellipsoids"], rgb) >= PRESENT_PIXELS, f"{name} ellipsoid"
        assert count_hue(images["plain"], rgb) <= ABSENT_PIXELS, (
            f"{name} colour without ellipsoids"
        )
    changed = np.abs(images["ellipsoids"] - images["plain"]).max(axis=-1) > 0.1
    assert changed.mean() > MIN_CHANGED


def test_static_html_plays_the_animation(
    chromium: str, model: og.ClosedLoopModel, tmp_path: Path
) -> None:
    viewer = Viewer(model)
    t = np.linspace(0.0, 2.0, 401)
    circle = np.stack([0.06 * np.cos(np.pi * t), 0.06 * np.sin(np.pi * t), 0.02 + 0 * t], -1)
    viewer.play((t, circle))
    page = viewer.save_html(tmp_path / "animation.html").as_uri()
    early = screenshot(chromium, page, "animation_early", budget_ms=800)
    late = screenshot(chromium, page, "animation_late", budget_ms=1900)
    for image in (early, late):
        assert_machine_drawn(image, viewer)
    # The legs moved between the two moments.
    changed = np.abs(early - late).max(axis=-1) > 0.1
    assert changed.mean() > MIN_CHANGED


def test_static_html_plays_a_natural_mode(
    chromium: str, model: og.ClosedLoopModel, tmp_path: Path
) -> None:
    viewer = Viewer(model)
    viewer.play_mode((0.05, 0.02, -0.03), 1, amplitude=0.04)
    page = viewer.save_html(tmp_path / "mode.html").as_uri()
    # half a period apart (2 s a period): the swing on either side of rest
    early = screenshot(chromium, page, "mode_early", budget_ms=800)
    late = screenshot(chromium, page, "mode_late", budget_ms=1800)
    for image in (early, late):
        assert_machine_drawn(image, viewer)
    changed = np.abs(early - late).max(axis=-1) > 0.1
    assert changed.mean() > MIN_CHANGED_MODE


def _first_line(process: subprocess.Popen[str], timeout: float) -> str:
    assert process.stdout is not None
    with selectors.DefaultSelector() as sel:
        sel.register(process.stdout, selectors.EVENT_READ)
        if not sel.select(timeout):
            process.kill()
            pytest.fail(f"no output from the viewer server within {timeout} s")
    return process.stdout.readline()


def test_live_server_in_the_browser(chromium: str, scenes: dict[str, Viewer]) -> None:
    args = [sys.executable, "-m", "orthoglide_pin", "view", "--ellipsoids", "grid", "--json"]
    process = subprocess.Popen(
        [*args, "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        line = _first_line(process, SERVER_TIMEOUT)
        assert line, process.stderr.read() if process.stderr else ""
        payload = json.loads(line)
        url = payload["url"]
        assert url.startswith("http://127.0.0.1:") and payload["ellipsoids"] == 27
        image = screenshot(chromium, url, "live_server")
        assert_machine_drawn(image, scenes["ellipsoids"])
        for name, rgb in ellipsoid_end_colours(scenes["ellipsoids"]).items():
            assert count_hue(image, rgb) >= PRESENT_PIXELS, f"{name} ellipsoid"
        process.send_signal(signal.SIGINT)
        assert process.wait(SERVER_TIMEOUT) == 130  # interrupted: one line, exit 128 + 2
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    port = int(url.rsplit(":", 1)[1].strip("/"))
    with pytest.raises(ConnectionRefusedError):
        socket.create_connection(("127.0.0.1", port), timeout=5).close()
