"""A natural mode played in the viewer: the animation's numbers against the mode shape."""

from __future__ import annotations

import base64
import json
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

import orthoglide_pin as og
from orthoglide_pin.cli import main
from orthoglide_pin.viewer import Viewer
from orthoglide_pin.viewer.modes import (
    DEFAULT_AMPLITUDE,
    DEFAULT_PERIOD,
    FRAMES_PER_PERIOD,
    mode_motion,
)
from orthoglide_pin.viewer.scene import unpack

ROOT = "/meshcat/orthoglide"
#: A point of the prototype's cube away from its symmetries [m].
POINT = (0.05, 0.02, -0.03)
#: Round-off of the animation's float64 tracks [m, rad].
TRACK_TOL = 1e-9
#: The mode's direction and rotation, recomputed by the model (the same call) [-].
SHAPE_TOL = 1e-9


def decoded(html: str) -> list[dict[str, Any]]:
    """The commands inlined in a static page, decoded from base64 msgpack."""
    match = re.search(r"var ogCommands = (\[.*?\]);", html)
    assert match is not None
    return [unpack(base64.b64decode(c)) for c in json.loads(match.group(1))]


def clips(viewer: Viewer) -> dict[str, dict[str, Any]]:
    (command,) = [c for c in decoded(viewer.html()) if c["type"] == "set_animation"]
    assert command["options"]["play"] is True
    return {a["path"]: a["clip"] for a in command["animations"]}


def track(clip: dict[str, Any], name: str) -> np.ndarray:
    (t,) = [t for t in clip["tracks"] if t["name"] == "." + name]
    return np.array([k["value"] for k in t["keys"]], dtype=float)


def placements(clip: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Positions (F, 3) and rotations (F, 3, 3) of a clip (quaternions x, y, z, w)."""
    return track(clip, "position"), Rotation.from_quat(track(clip, "quaternion")).as_matrix()


def end_joint(model: og.ClosedLoopModel, q: np.ndarray, leg: int) -> np.ndarray:
    pin.forwardKinematics(model.model, model.data, q)
    return np.array(model.data.oMi[model.model.getJointId(f"leg{leg}_end_revolute")].translation)


@pytest.mark.parametrize("number", [1, 3])
def test_the_frames_swing_the_platform_along_the_mode(
    model: og.ClosedLoopModel, number: int
) -> None:
    viewer = Viewer(model)
    motion = viewer.play_mode(POINT, number)
    shape = og.natural_frequencies(model.params, POINT, count=number)
    d, w = shape.direction[number - 1], shape.rotation[number - 1]
    found = clips(viewer)
    centre, turn = placements(found[f"{ROOT}/machine/platform_0"])
    assert len(centre) == FRAMES_PER_PERIOD + 1
    # the tool tip, carried by the platform's clip from its place at rest
    p0 = np.asarray(POINT)
    tip = centre + np.einsum("fij,j->fi", turn, p0 - centre[0])
    swing = tip - p0
    along = swing @ d
    np.testing.assert_allclose(swing, along[:, None] * d, atol=TRACK_TOL)
    times = np.linspace(0.0, DEFAULT_PERIOD, FRAMES_PER_PERIOD + 1)
    size = np.abs(along).max()
    np.testing.assert_allclose(
        along, size * np.sin(2 * math.pi * times / DEFAULT_PERIOD), atol=1e-12
    )
    # the platform turns by the mode's rotation per metre of tool motion
    np.testing.assert_allclose(
        Rotation.from_matrix(turn).as_rotvec(), along[:, None] * w, atol=TRACK_TOL
    )
    # the drawn amplitude: the farthest of the tool tip and the platform's joints
    joints = np.array([end_joint(model, motion.configurations[0], i) for i in (1, 2, 3)]) - p0
    reach = np.linalg.norm(joints, axis=1).max()
    expected = DEFAULT_AMPLITUDE * model.params.workspace.side
    assert max(size, size * np.linalg.norm(w) * reach) == pytest.approx(expected, rel=1e-9)
    # each leg closes on the turned platform: its end joint is where the platform has it
    for i in (1, 2, 3):
        ends = np.array([end_joint(model, q, i) for q in motion.configurations])
        on_platform = tip + np.einsum("fij,j->fi", turn, joints[i - 1])
        np.testing.assert_allclose(ends, on_platform, atol=TRACK_TOL)
        # the carriage runs along its rail only, with the slider of that leg
        carriage, _ = placements(found[f"{ROOT}/machine/leg{i}_carriage_0"])
        moved = carriage - carriage[0]
        np.testing.assert_allclose(np.delete(moved, i - 1, axis=1), 0.0, atol=TRACK_TOL)
        slider = motion.configurations[:, model.actuated[i - 1]]
        np.testing.assert_allclose(moved[:, i - 1], slider - slider[0], atol=TRACK_TOL)
        assert np.ptp(slider) > 0.0
    # the rails stay put
    assert f"{ROOT}/machine/leg1_rail_0" not in found


def test_another_design_and_the_full_model() -> None:
    other = og.prototype().replace(
        leg_length=0.36, workspace_corner=(-0.06, -0.05, -0.07), workspace_side=0.15
    )
    point = (0.03, -0.02, 0.04)
    motion = mode_motion(
        og.ClosedLoopModel(other), point, 2, vibration_model="full", amplitude=0.004
    )
    full = og.natural_frequencies(other, point, count=2, model="full")
    assert motion.frequency == pytest.approx(full.frequencies[1], rel=SHAPE_TOL)
    np.testing.assert_allclose(motion.direction, full.direction[1], atol=SHAPE_TOL)
    tips = motion.frames.points - np.asarray(point)
    assert np.abs(tips @ motion.direction).max() == pytest.approx(motion.scale, rel=1e-12)
    reach = np.linalg.norm(motion.attachments, axis=1).max()
    assert max(1.0, np.linalg.norm(motion.rotation) * reach) * motion.scale == pytest.approx(
        0.004, rel=1e-12
    )


@pytest.mark.parametrize(
    ("point", "mode", "options", "name"),
    [
        (POINT, 0, {}, "mode"),
        (POINT, 7, {}, "mode"),
        (POINT, True, {}, "mode"),
        ((0.2, 0.0, 0.0), 1, {}, "point"),  # outside the cube
        ((math.nan, 0.0, 0.0), 1, {}, "point"),
        (POINT, 1, {"amplitude": 0.2}, "amplitude"),
        (POINT, 1, {"amplitude": -1.0}, "amplitude"),
        (POINT, 1, {"vibration_model": "beam"}, "vibration_model"),
        (POINT, 1, {"period": 0.0}, "period"),
    ],
)
def test_bad_input_is_refused(
    model: og.ClosedLoopModel, point: Any, mode: Any, options: dict[str, Any], name: str
) -> None:
    with pytest.raises(og.InvalidParameterError) as info:
        mode_motion(model, point, mode, **options)
    assert info.value.name == name


def test_a_rotation_about_the_tool_tip_is_refused(
    model: og.ClosedLoopModel, monkeypatch: pytest.MonkeyPatch
) -> None:
    import dataclasses

    from orthoglide_pin.elasticity import modes

    real = modes.natural_frequencies

    def turning(*args: Any, **kwargs: Any) -> Any:
        out = real(*args, **kwargs)
        direction = out.direction.copy()
        direction[..., 5:, :] = 0.0  # the sixth mode turns the platform about the tool tip
        return dataclasses.replace(out, direction=direction)

    monkeypatch.setattr(modes, "natural_frequencies", turning)
    with pytest.raises(og.InvalidParameterError) as info:
        mode_motion(model, POINT, 6)
    assert info.value.name == "mode"
    mode_motion(model, POINT, 5)  # the others are drawn


def test_the_command_saves_the_animated_page(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, model: og.ClosedLoopModel
) -> None:
    out = tmp_path / "mode.html"
    args = ["view", "--mode", "1", "--at", "0.05,0.02,-0.03", "--static", str(out)]
    assert main([*args, "--amplitude", "0.02", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    mode = data["mode"]
    shape = og.natural_frequencies(og.prototype(), POINT, count=1)
    assert mode["frequency"] == pytest.approx(shape.frequencies[0], rel=SHAPE_TOL)
    np.testing.assert_allclose(mode["tool_direction"], shape.direction[0], atol=SHAPE_TOL)
    assert data["frames"] == FRAMES_PER_PERIOD + 1
    rest = model.configuration(POINT)
    reach = max(np.linalg.norm(end_joint(model, rest, i) - POINT) for i in (1, 2, 3))
    turn = np.linalg.norm(shape.rotation[0]) * reach
    assert mode["swing"] == pytest.approx(0.02 / max(1.0, turn), rel=1e-9)
    # one self-contained page that plays the mode: every moving part has its clip
    commands = decoded(out.read_text())
    (command,) = [c for c in commands if c["type"] == "set_animation"]
    paths = {a["path"] for a in command["animations"]}
    assert {f"{ROOT}/machine/platform_0", f"{ROOT}/machine/leg3_carriage_0"} <= paths


@pytest.mark.parametrize(
    "args",
    [
        ["--mode", "0", "--at", "0", "0", "0"],
        ["--mode", "7", "--at", "0", "0", "0"],
        ["--mode", "1", "--at", "0.2", "0", "0"],
        ["--mode", "1", "--at", "0", "0"],
        ["--mode", "1"],
        ["--at", "0", "0", "0"],
        ["--mode", "1", "--at", "0", "0", "0", "--trajectory", "diagonal"],
        ["--mode", "x", "--at", "0", "0", "0"],
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, args: list[str]
) -> None:
    out = tmp_path / "mode.html"
    assert main(["view", *args, "--static", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "error" in err
    assert not out.exists()
