"""The optimal route: the plan streamed by HAL's ``streamer`` at the servo rate.

In a LinuxCNC session (``controller._session``, started once for the test
run): the exported configuration's own streamer plays each design's streams
(a raster of 10,041 short blocks, the cube's diagonals), started and stopped by
the display program, the joints sampled every servo period. Standalone:
``orthoglide plan contour.nc --out DIR --linuxcnc DIR2`` writes the stream (the
program read in the design's program axes, as for the plan itself), and its
``orthoglide_stream.hal`` is run with ``halrun`` (a HAL ``sampler`` added on
the same thread). Both ways: the joints' peak speed and acceleration within
100.1 % of their limits, the cycle time the plan's within 1 %, and the tool
(forward kinematics of the streamed joints) on the plan's path within 1
micrometre.
"""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from controller._session import (
    SLIDER_ACCELERATION,
    SLIDER_SPEED,
    STREAM_CASES,
    peaks,
)
from controller._support import require, rtapi_env, run_session

from orthoglide_pin.cli import main
from orthoglide_pin.controller.stream import STREAM_FILES, STREAM_PERIOD
from orthoglide_pin.kinematics.closed_form import direct_kinematics
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.shipped import example_program_text

pytestmark = pytest.mark.slow

#: Cycle time agreement [-] and path agreement [m].
TIME_TOL, PATH_TOL = 0.01, 1e-6
#: Extra periods recorded after the stream's end.
TAIL = 300
#: Allowed peak use of a joint limit.
PEAK_USE = 1.001


@pytest.fixture(scope="module")
def streamed(tmp_path_factory: pytest.TempPathFactory) -> tuple:
    tools = require("halrun", "halstreamer", "halsampler")
    params = OrthoglideParams()
    top = tmp_path_factory.mktemp("stream")
    program, folder = top / "contour.nc", top / "cnc"
    program.write_text(example_program_text("contour"))
    argv = ["plan", str(program), "--out", str(top / "plan"), "--linuxcnc", str(folder)]
    argv += ["--max-slider-speed", "1.2", "--max-slider-acceleration", "20"]
    assert main(argv) == 0
    plan = json.loads((top / "plan" / "plan.json").read_text())
    rows = np.genfromtxt(top / "plan" / "trajectory.csv", delimiter=",", names=True, skip_header=1)
    columns = {name: rows[name] for name in ("t", "x", "y", "z", "q1", "q2", "q3")}
    n = len(columns["t"])
    assert len((folder / STREAM_FILES[0]).read_text().splitlines()) == n
    hal = (
        (folder / STREAM_FILES[1])
        .read_text()
        .replace(
            "loadusr -w halstreamer plan.stream",
            "loadrt sampler depth=4096 cfg=fff\naddf sampler.0 servo-thread\n"
            + "\n".join(f"net q{k} => sampler.0.pin.{k}" for k in range(3))
            + "\nloadusr -w ./play.sh",
        )
    )
    # the sampler must be added before the thread starts
    hal = hal.replace("start\n", "").replace("loadusr -w ./play.sh", "start\nloadusr -w ./play.sh")
    (folder / "orthoglide_stream.hal").write_text(hal)
    play = folder / "play.sh"
    play.write_text(
        f"#!/bin/sh\nhalstreamer plan.stream &\nhalsampler -n {n + TAIL} > out.samples\nwait\n"
    )
    play.chmod(0o755)
    sockets = Path(tempfile.mkdtemp(prefix="orthoglide-rtapi-"))
    sockets.chmod(0o777)
    env = rtapi_env(sockets)
    try:
        run_session([tools["halrun"], "-f", "orthoglide_stream.hal"], folder, env, timeout=120)
    finally:
        shutil.rmtree(sockets, ignore_errors=True)
    lines = (folder / "out.samples").read_text().splitlines()
    assert "overrun" not in "".join(lines), "the sampler lost samples"
    samples = 1e-3 * np.array([[float(w) for w in x.split()] for x in lines])
    return params, plan, columns, samples


def _check_played(
    name: str, samples: np.ndarray, columns: dict, cycle_time: float, params
) -> None:
    """Cycle time and path of ``samples`` (played joints [m]) against the plan's ``columns``."""
    q = np.stack([columns["q1"], columns["q2"], columns["q3"]], axis=1)
    # the stream begins where the played samples first equal its first moving row
    move = np.flatnonzero(np.abs(np.diff(q, axis=0)).max(axis=1) > 1e-9)
    played = np.flatnonzero(np.abs(np.diff(samples, axis=0)).max(axis=1) > 1e-9)
    cycle = (move[-1] - move[0]) * STREAM_PERIOD
    played_cycle = (played[-1] - played[0]) * STREAM_PERIOD
    shift = played[0] - move[0]
    j = samples[shift : shift + len(q)]
    tool = direct_kinematics(j, params.leg_length, check_limits=False)
    path = np.stack([columns["x"], columns["y"], columns["z"]], axis=1)
    off = np.linalg.norm(tool - path, axis=1).max()
    print(
        f"{name} streamed: {played_cycle:.3f} s, plan {cycle_time:.3f} s, "
        f"off the plan's path by {1e9 * off:.1f} nm"
    )
    assert abs(played_cycle - cycle_time) <= TIME_TOL * cycle_time
    assert abs(played_cycle - cycle) <= 2 * STREAM_PERIOD
    assert len(j) == len(q)
    assert off <= PATH_TOL


def test_cycle_time_and_path_are_the_plans(streamed: tuple) -> None:
    params, plan, columns, samples = streamed
    _check_played("contour (halrun)", samples, columns, plan["cycle_time"], params)
    speed, accel = peaks(np.hstack([np.arange(len(samples))[:, None], 1e3 * samples]))
    assert speed <= PEAK_USE * SLIDER_SPEED
    assert accel <= PEAK_USE * SLIDER_ACCELERATION


@pytest.mark.parametrize(("design", "program"), STREAM_CASES)
def test_streamed_in_a_linuxcnc_session(run: dict, design: str, program: str) -> None:
    """The configuration's streamer in ``linuxcnc -r``: limits, cycle time and path."""
    done = run[design]
    data, plan = done["streams"][program], done["plans"][program]
    assert not data["errors"], data["errors"]
    speed, accel = peaks(data["samples"])
    limit_v, limit_a = run[design]["joint_speed"], run[design]["joint_acceleration"]
    print(
        f"{design} {program} streamed: peak joint speed {1e3 * speed:.1f} mm/s "
        f"({100 * speed / limit_v:.1f} %), acceleration {1e3 * accel:.0f} mm/s^2 "
        f"({100 * accel / limit_a:.1f} %)"
    )
    assert speed <= PEAK_USE * limit_v  # the [JOINT_n] limits
    assert accel <= PEAK_USE * limit_a
    samples = 1e-3 * data["samples"][:, 1:4]
    _check_played(
        f"{design} {program}", samples, plan["columns"], plan["cycle_time"], done["params"]
    )


@pytest.mark.parametrize("design", sorted({d for d, _ in STREAM_CASES}))
def test_a_stream_elsewhere_is_refused(run: dict, design: str) -> None:
    """``orthoglide_play.py`` refuses a stream that does not start at the joints: nothing moves."""
    refused = run[design]["refused"]
    assert refused["status"] == 2
    assert "starts at" in refused["stderr"] and "the joints are at" in refused["stderr"]
    assert refused["moved"] == 0.0
    assert refused["on"]
