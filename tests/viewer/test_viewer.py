"""The meshcat viewer without a browser: scene, static HTML, animation, server, CLI."""

from __future__ import annotations

import asyncio
import base64
import json
import math
import re
import socket
import subprocess
import sys
import urllib.request
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import CUBE_CORNER, CUBE_SIDE, PROTOTYPE_LEG, cube_points

import orthoglide_pin as og
from orthoglide_pin.cli import main
from orthoglide_pin.cli.view import TRAJECTORIES, named_trajectory
from orthoglide_pin.viewer import Viewer, animation, overlays
from orthoglide_pin.viewer.scene import Scene, unpack
from orthoglide_pin.viewer.server import SceneServer

#: Loop closure in the exported frames [m] (positions are float64, quaternions normalised).
CLOSURE_TOL = 1e-9
#: Agreement of ellipsoid shapes with J J^T (relative).
SHAPE_RTOL = 1e-9
#: Agreement of quaternions with meshcat's own conversion.
QUAT_TOL = 1e-9
#: Round-off of values computed two ways in float64 [m, rad].
EXACT_TOL = 1e-12
#: Newton's loop closure against the closed form [m, rad].
SOLVE_TOL = 1e-9
#: Relative round-off of the cube's float32 vertices.
FLOAT32_RTOL = 1e-6
#: Distance of the first and of the nearest sample of a cycle part to a corner
#: (samples fall at k dt, not at the segment's start) [m].
SAMPLE_TOL = 1e-6
#: Colour resolution of a material (0xRRGGBB rounding).
COLOR_TOL = 0.5 / 255 + 1e-6
#: Seconds to wait at most for a live server's page and websocket messages.
SOCKET_TIMEOUT = 60.0
ROOT = "/meshcat/orthoglide"


# ----------------------------------------------------------------- helpers
def decoded_commands(html: str) -> list[dict[str, Any]]:
    """The commands inlined in a static page, decoded from base64 msgpack."""
    match = re.search(r"var ogCommands = (\[.*?\]);", html)
    assert match is not None
    return [unpack(base64.b64decode(c)) for c in json.loads(match.group(1))]


def quaternion_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion (x, y, z, w), textbook formula."""
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def track(clip: dict[str, Any], name: str) -> np.ndarray:
    (t,) = [t for t in clip["tracks"] if t["name"] == "." + name]
    return np.array([k["value"] for k in t["keys"]], dtype=float)


def urdf_visuals(urdf: str) -> list[tuple[str, ET.Element, tuple[float, ...]]]:
    """(link, geometry element, rgba) of every <visual> of a URDF, read with ElementTree."""
    root = ET.fromstring(urdf)
    colors = {
        m.get("name"): tuple(float(v) for v in m.find("color").get("rgba").split())
        for m in root.findall("material")
    }
    out = []
    for link in root.findall("link"):
        for visual in link.findall("visual"):
            geometry = visual.find("geometry")
            assert geometry is not None and len(geometry) == 1
            material = visual.find("material")
            rgba = colors[material.get("name")] if material is not None else (0.9, 0.9, 0.9, 1.0)
            out.append((str(link.get("name")), geometry[0], rgba))
    return out


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def viewer(model: og.ClosedLoopModel) -> Viewer:
    v = Viewer(model)
    v.add_workspace()
    return v


@pytest.fixture(scope="module")
def circle() -> tuple[np.ndarray, np.ndarray]:
    """A circle of radius 60 mm at z = 20 mm in 2 s, sampled at 1 kHz."""
    t = np.linspace(0.0, 2.0, 2001)
    angle = np.pi * t
    return t, np.stack([0.06 * np.cos(angle), 0.06 * np.sin(angle), 0.02 + 0 * t], -1)


@pytest.fixture(scope="module")
def animated(model: og.ClosedLoopModel, circle: tuple[np.ndarray, np.ndarray]) -> Viewer:
    v = Viewer(model)
    v.add_ellipsoids(v.grid_points(3))
    v.play(circle)
    return v


# --------------------------------------------------------------- the scene
def test_scene_is_built_and_exported_without_a_server(viewer: Viewer) -> None:
    import threading

    threads = threading.active_count()
    html = viewer.html()
    assert viewer.url() is None
    assert threading.active_count() == threads
    # Self-contained: the viewer script is inline, nothing is fetched.
    assert re.search(r"<script[^>]*\bsrc\s*=", html) is None
    assert re.search(r"<link\b", html) is None
    assert re.search(r"""(src|href)\s*=\s*["']?https?:""", html) is None
    assert "MeshCat.Viewer" in html and len(html) > 800_000
    assert decoded_commands(html) == viewer.scene.commands()


def test_every_urdf_visual_is_drawn_with_its_size_and_colour(
    viewer: Viewer, params: og.OrthoglideParams
) -> None:
    expected = urdf_visuals(og.render_urdf(params))
    assert len(expected) == 21  # 6 per leg, platform, spindle, tool
    objects = [
        c
        for c in decoded_commands(viewer.html())
        if c["type"] == "set_object" and "/machine/" in c["path"]
    ]
    assert len(objects) == len(expected)
    by_link = {c["path"].rsplit("/", 1)[1].rsplit("_", 1)[0]: c["object"] for c in objects}
    assert sorted(by_link) == sorted(link for link, _, _ in expected)
    names = {"bar_a", "bar_b", "carriage", "rail", "base_link", "end_link"}
    assert {f"leg{i}_{n}" for i in (1, 2, 3) for n in names} | {
        "platform",
        "spindle",
        "tool",
    } == set(by_link)
    for link, geometry, rgba in expected:
        obj = by_link[link]
        (geo,) = obj["geometries"]
        (mat,) = obj["materials"]
        color = [(mat["color"] >> s & 255) / 255 for s in (16, 8, 0)]
        np.testing.assert_allclose(color, rgba[:3], atol=COLOR_TOL)
        if geometry.tag == "box":
            size = [float(v) for v in str(geometry.get("size")).split()]
            np.testing.assert_allclose([geo["width"], geo["height"], geo["depth"]], size)
        else:
            assert geometry.tag == "cylinder"
            assert geo["radiusTop"] == pytest.approx(float(str(geometry.get("radius"))))
            assert geo["height"] == pytest.approx(float(str(geometry.get("length"))))


def test_machine_follows_the_tool_point(viewer: Viewer, model: og.ClosedLoopModel) -> None:
    point = np.array([0.05, -0.03, 0.08])
    try:
        viewer.show_point(point)
        platform = viewer.scene.transform(f"{ROOT}/machine/platform_0")
        assert platform is not None
        # The platform centre sits tool_offset below the tool tip, axes unchanged.
        np.testing.assert_allclose(
            platform[:3, 3], point - model.params.tool_offset, atol=EXACT_TOL
        )
        np.testing.assert_allclose(platform[:3, :3], np.eye(3), atol=EXACT_TOL)
        # Same drawing from the slider values, loops closed by Newton.
        q = og.inverse_kinematics(point, PROTOTYPE_LEG)
        again = viewer.show_sliders(q)
        np.testing.assert_allclose(again, model.configuration(point), atol=SOLVE_TOL)
    finally:
        viewer.show(model.neutral())


# ---------------------------------------------------------------- overlays
def test_ellipsoids_are_the_images_of_the_unit_ball(model: og.ClosedLoopModel) -> None:
    v = Viewer(model)
    points = cube_points(6, seed=5)
    scale = 0.02
    for kind in ("velocity", "force"):
        ells = v.add_ellipsoids(points, kind, scale=scale)
        assert len(v.scene.paths(f"{ROOT}/ellipsoids")) == len(points)
        J = og.jacobian(points, PROTOTYPE_LEG)
        for k, p in enumerate(points):
            m = v.scene.transform(f"{ROOT}/ellipsoids/{k}")
            assert m is not None
            np.testing.assert_allclose(m[:3, 3], p)
            a = m[:3, :3]
            assert np.linalg.det(a) > 0  # a rotation times positive scales: no reflection
            shape = J[k] @ J[k].T if kind == "velocity" else np.linalg.inv(J[k] @ J[k].T)
            np.testing.assert_allclose(
                a @ a.T, scale**2 * shape, rtol=SHAPE_RTOL, atol=EXACT_TOL**2
            )
            assert ells.condition[k] == pytest.approx(np.linalg.cond(J[k]), rel=SHAPE_RTOL)


def test_ellipsoid_colours_follow_the_condition_number(model: og.ClosedLoopModel) -> None:
    v = Viewer(model)
    grid = v.grid_points(3)
    ells = v.add_ellipsoids(grid)
    commands = v.scene.commands()
    colors = {
        c["path"]: c["object"]["materials"][0]["color"]
        for c in commands
        if c["type"] == "set_object" and "/ellipsoids/" in c["path"]
    }
    rgb = np.array(
        [
            [(colors[f"{ROOT}/ellipsoids/{k}"] >> s & 255) / 255 for s in (16, 8, 0)]
            for k in range(27)
        ]
    )
    # "cool": red rises from 0 (cyan, condition 1) to 1 (magenta, the largest).
    order = np.argsort(ells.condition)
    assert np.all(np.diff(rgb[order, 0]) >= -COLOR_TOL)
    np.testing.assert_allclose(rgb[order[-1]], [1.0, 0.0, 1.0], atol=COLOR_TOL)
    assert v.scene.legend is not None
    assert v.scene.legend["min"] == 1.0
    assert v.scene.legend["max"] == pytest.approx(ells.condition.max())
    # The prototype's grid is worst conditioned at Q2, about 4 (paper: factors 0.5 and 2
    # there; L = 310 mm is rounded), and exactly 2.5 at Q1 (factors 2 and 0.8).
    q2 = np.full(3, CUBE_CORNER + CUBE_SIDE)
    np.testing.assert_allclose(grid[np.argmax(ells.condition)], q2)
    assert ells.condition.max() == pytest.approx(4.0, rel=1e-2)
    np.testing.assert_allclose(grid[np.argmin(np.abs(ells.condition - 2.5))], CUBE_CORNER)
    v.clear_ellipsoids()
    assert v.scene.paths(f"{ROOT}/ellipsoids") == []


def test_workspace_overlay_marks_q1_q2_and_the_isotropic_point(viewer: Viewer) -> None:
    where = {
        "isotropic_point": np.zeros(3),
        "Q1": np.full(3, CUBE_CORNER),
        "Q2": np.full(3, CUBE_CORNER + CUBE_SIDE),
    }
    for name, point in where.items():
        m = viewer.scene.transform(f"{ROOT}/workspace/{name}")
        assert m is not None
        np.testing.assert_allclose(m[:3, 3], point, atol=EXACT_TOL)
    (cube,) = [c for c in viewer.scene.commands() if c["path"] == f"{ROOT}/workspace/cube"]
    geometry = cube["object"]["geometries"][0]["data"]["attributes"]["position"]
    vertices = np.frombuffer(geometry["array"].data, dtype=np.float32).reshape(-1, 3)
    assert vertices.shape == (24, 3)  # 12 edges
    edges = np.linalg.norm(vertices[0::2] - vertices[1::2], axis=1)
    np.testing.assert_allclose(edges, CUBE_SIDE, rtol=FLOAT32_RTOL)
    np.testing.assert_allclose(vertices.min(axis=0), CUBE_CORNER, rtol=FLOAT32_RTOL)


def test_the_viewer_takes_the_parameters_of_another_design() -> None:
    other = og.prototype().replace(
        leg_length=0.36, workspace_corner=(-0.06, -0.05, -0.07), workspace_side=0.15
    )
    viewer, built = Viewer(other), Viewer(og.ClosedLoopModel(other))
    assert viewer.model.params == other
    paths = [(c["type"], c["path"]) for c in viewer.scene.commands()]
    assert paths == [(c["type"], c["path"]) for c in built.scene.commands()]
    for _, path in paths:
        a, b = viewer.scene.transform(path), built.scene.transform(path)
        assert (a is None) == (b is None)
        if a is not None:
            np.testing.assert_array_equal(a, b)
    # the workspace drawn is that design's cube
    viewer.add_workspace()
    m = viewer.scene.transform(f"{ROOT}/workspace/Q2")
    assert m is not None
    np.testing.assert_allclose(m[:3, 3], other.workspace.q2, atol=EXACT_TOL)
    with pytest.raises(og.InvalidParameterError) as info:
        Viewer("prototype")  # type: ignore[arg-type]
    assert info.value.name == "model"


# --------------------------------------------------------------- animation
def test_quaternions_match_meshcat_on_every_kind_of_rotation() -> None:
    import meshcat.transformations as tf

    rng = np.random.default_rng(3)
    rotations = [tf.random_rotation_matrix(rng.random(3))[:3, :3] for _ in range(200)]
    # Half turns (w = 0) about oblique axes: signs must stay consistent.
    for axis in ([1, 1, 0], [0, 1, 1], [1, 0, -1], [1, 2, 3]):
        rotations.append(tf.rotation_matrix(math.pi, axis)[:3, :3])
    q = animation.quaternions(np.array(rotations))
    for r, qk in zip(rotations, q, strict=True):
        ref = tf.quaternion_from_matrix(np.block([[r, np.zeros((3, 1))], [np.zeros((1, 3)), 1]]))
        ref = np.array([ref[1], ref[2], ref[3], ref[0]])
        assert min(np.abs(qk - ref).max(), np.abs(qk + ref).max()) < QUAT_TOL
        np.testing.assert_allclose(quaternion_matrix(qk), r, atol=EXACT_TOL)


def test_resampling_keeps_ends_and_scales_time(circle: tuple[np.ndarray, np.ndarray]) -> None:
    t, p = circle
    frames = animation.resample(t, p, fps=30.0)
    assert len(frames.times) == 61 and frames.fps == pytest.approx(30.0)
    np.testing.assert_allclose(frames.points[[0, -1]], p[[0, -1]])
    slow = animation.resample(t, p, fps=30.0, time_scale=2.0)
    assert slow.times[-1] == pytest.approx(4.0) and len(slow.times) == 121
    np.testing.assert_allclose(slow.points[::2], frames.points, atol=EXACT_TOL)
    capped = animation.resample(t, p, fps=1000.0, max_frames=50)
    assert len(capped.times) == 50 and capped.fps == pytest.approx(49 / 2.0)
    with pytest.raises(og.InvalidParameterError, match="trajectory times"):
        animation.resample(t[::-1], p)


def test_animation_frames_keep_every_loop_closed(
    animated: Viewer, circle: tuple[np.ndarray, np.ndarray], params: og.OrthoglideParams
) -> None:
    (command,) = [c for c in decoded_commands(animated.html()) if c["type"] == "set_animation"]
    clips = {a["path"]: a["clip"] for a in command["animations"]}
    frames = animation.resample(*circle)
    w = params.parallelogram_width
    for i in (1, 2, 3):
        bar = clips[f"{ROOT}/machine/leg{i}_bar_b_0"]
        link = clips[f"{ROOT}/machine/leg{i}_end_link_0"]
        gaps = []
        for pb, qb, pl, ql in zip(
            track(bar, "position"),
            track(bar, "quaternion"),
            track(link, "position"),
            track(link, "quaternion"),
            strict=True,
        ):
            # The bar's cylinder runs along its z axis, tip at +L/2; the end link's
            # along its z axis, bar b's joint at +w/2 (URDF origins).
            tip = pb + 0.5 * params.leg_length * quaternion_matrix(qb)[:, 2]
            joint = pl + 0.5 * w * quaternion_matrix(ql)[:, 2]
            gaps.append(np.linalg.norm(tip - joint))
        assert len(gaps) == len(frames.times)
        assert max(gaps) < CLOSURE_TOL
    platform = clips[f"{ROOT}/machine/platform_0"]
    np.testing.assert_allclose(
        track(platform, "position"), frames.points - params.tool_offset, atol=EXACT_TOL
    )
    keys = [k["time"] for k in platform["tracks"][0]["keys"]]
    np.testing.assert_allclose(np.array(keys) / platform["fps"], frames.times, atol=EXACT_TOL)
    # The rails do not move: no clip; the follower has scale and colour tracks.
    assert f"{ROOT}/machine/leg1_rail_0" not in clips
    follower = clips[f"{ROOT}/follower"]
    scales = track(follower, "scale") / overlays.ELLIPSOID_SCALE
    factors = og.transmission_factors(frames.points, params.leg_length)
    np.testing.assert_allclose(np.sort(scales, axis=1), factors, rtol=SHAPE_RTOL)
    assert len(track(clips[f"{ROOT}/follower/<object>"], "material.color")) == len(frames.times)
    assert command["options"]["play"] is True


def test_static_html_is_written_atomically(animated: Viewer, tmp_path: Path) -> None:
    path = animated.save_html(tmp_path / "sub" / "scene.html")
    assert path.read_text(encoding="utf-8") == animated.html()
    assert sorted(p.name for p in path.parent.iterdir()) == ["scene.html"]


def test_notebook_display(animated: Viewer) -> None:
    html = animated._repr_html_()
    assert html.startswith("<iframe srcdoc=") and "&lt;script&gt;" in html
    assert "Live viewer" not in html


# ------------------------------------------------------------------ server
def test_nothing_is_started_at_import() -> None:
    code = (
        "import os, threading, multiprocessing\n"
        "import orthoglide_pin, orthoglide_pin.viewer, orthoglide_pin.cli.view\n"
        "from orthoglide_pin.viewer import server, visualizer, animation, machine, scene\n"
        "scene.meshcat('geometry'), scene.meshcat('animation')\n"
        "fds = []\n"
        "for f in os.listdir('/proc/self/fd'):\n"
        "    try: fds.append(os.readlink(f'/proc/self/fd/{f}'))\n"
        "    except OSError: pass\n"
        "print(threading.active_count(), len(multiprocessing.active_children()),"
        " sum(f.startswith('socket:') for f in fds))\n"
    )
    if not Path("/proc/self/fd").is_dir():
        pytest.skip("needs /proc to list open sockets")
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["1", "0", "0"]


def test_port_in_use_is_a_clear_error(capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen(1)
        port = holder.getsockname()[1]
        with pytest.raises(og.PortInUseError, match=f"port {port} on 127.0.0.1 is in use") as info:
            SceneServer(Scene(), port)
        assert info.value.port == port
        assert main(["view", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"orthoglide view: error: port {port}")


async def _receive(url: str, count: int) -> list[bytes | str]:
    import tornado.websocket

    conn = await tornado.websocket.websocket_connect(url.replace("http", "ws") + "ws")
    out: list[bytes | str] = []
    while len(out) < count:
        msg = await asyncio.wait_for(conn.read_message(), SOCKET_TIMEOUT)
        assert msg is not None
        out.append(msg)
    conn.close()
    return out


def test_live_server_sends_the_scene_and_frees_its_port(model: og.ClosedLoopModel) -> None:
    v = Viewer(model)
    v.add_ellipsoids(v.grid_points(2))
    url = v.serve(0)
    try:
        assert url.startswith("http://127.0.0.1:") and v.url() == url
        assert v.serve(0) == url  # already serving
        page = urllib.request.urlopen(url, timeout=SOCKET_TIMEOUT).read().decode()
        assert "WebSocket" in page and 'src="/static/main.min.js"' in page
        script = urllib.request.urlopen(url + "static/main.min.js", timeout=SOCKET_TIMEOUT).read()
        assert b"MeshCat" in script
        commands = v.scene.commands()
        messages = asyncio.run(_receive(url, 1 + len(commands)))
        assert json.loads(messages[0])["legend"]["title"].startswith("condition number")
        assert [unpack(m) for m in messages[1:]] == commands
        assert "Live viewer" in v._repr_html_() and url in v._repr_html_()
    finally:
        v.close()
    assert v.url() is None
    port = int(url.rsplit(":", 1)[1].strip("/"))
    with pytest.raises(ConnectionRefusedError):  # nothing listens any more
        socket.create_connection(("127.0.0.1", port), timeout=5).close()
    SceneServer(Scene(), port).close()  # and a new server can take the port


def test_live_server_pushes_new_commands(model: og.ClosedLoopModel) -> None:
    v = Viewer(model)
    with SceneServer(v.scene, 0) as server:
        before = len(v.scene.commands())

        async def scenario() -> list[bytes | str]:
            import tornado.websocket

            conn = await tornado.websocket.websocket_connect(f"ws://127.0.0.1:{server.port}/ws")
            for _ in range(1 + before):
                await asyncio.wait_for(conn.read_message(), SOCKET_TIMEOUT)
            v.show_point([0.02, 0.0, 0.0])  # recorded in this thread, sent by the server's
            out = [await asyncio.wait_for(conn.read_message(), SOCKET_TIMEOUT) for _ in range(21)]
            conn.close()
            return [m for m in out if m is not None]

        messages = asyncio.run(scenario())
    assert [unpack(m)["type"] for m in messages] == ["set_transform"] * 21
    assert not server.running


# --------------------------------------------------------------------- CLI
def test_cli_writes_a_static_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "view.html"
    argv = [
        "view",
        "--json",
        "--ellipsoids",
        "grid",
        "--trajectory",
        "circle-xy",
        "--static",
        str(target),
    ]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["ellipsoids"] == 27 and payload["visuals"] == 21 and payload["frames"] > 10
    assert payload["static"] == str(target.resolve()) and "url" not in payload
    kinds = [c["type"] for c in decoded_commands(target.read_text(encoding="utf-8"))]
    assert kinds[-1] == "set_animation"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--ellipsoids", "0,0"], "invalid --ellipsoids='0,0'"),
        (["--ellipsoids", "1,1,1"], "unreachable"),
        (["--point", "0,nan,0"], "invalid --point"),
        (["--param", "leg_length=-1"], "leg_length"),
    ],
)
def test_cli_bad_input_is_one_line(
    argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["view", *argv, "--static", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert not (tmp_path / "x.html").exists()


def test_named_trajectories_are_parts_of_the_standard_cycle(params: og.OrthoglideParams) -> None:
    centre = np.full(3, CUBE_CORNER + CUBE_SIDE / 2)
    t, p = named_trajectory("circle-xy", params)
    assert np.all(np.diff(t) > 0)
    np.testing.assert_allclose(
        np.linalg.norm(p[:, :2] - centre[:2], axis=1), CUBE_SIDE / 4, atol=SOLVE_TOL
    )
    np.testing.assert_allclose(p[:, 2], centre[2], atol=EXACT_TOL)
    t, p = named_trajectory("diagonal", params)
    np.testing.assert_allclose(p[0], CUBE_CORNER, atol=SAMPLE_TOL)
    assert np.abs(p - (CUBE_CORNER + CUBE_SIDE)).max(axis=1).min() < SAMPLE_TOL  # reaches Q2
    for name in TRAJECTORIES:
        t, p = named_trajectory(name, params)
        assert len(t) > 100 and np.all(
            (p >= CUBE_CORNER - EXACT_TOL) & (p <= CUBE_CORNER + CUBE_SIDE + EXACT_TOL)
        )
    with pytest.raises(og.InvalidParameterError, match="--trajectory"):
        named_trajectory("spiral", params)
