"""The exported configuration run headless in LinuxCNC (started once for the module).

The component is built and installed under a name of its own
(``halcompile --install``: LinuxCNC 2.9 loads modules from its own folder
only) and removed at the end. LinuxCNC runs ``orthoglide.ini`` with the
display program ``linuxcnc_ui.py`` (system Python, ``linuxcnc`` module) and a
HAL ``sampler`` on the servo thread; as root, ``RTAPI_UID`` is an ordinary user
and ``RTAPI_FIFO_PATH`` a socket in a folder it can write. Every process started
(LinuxCNC, its ``rtapi_app``, ``milltask``, ``io``, ``halsampler``) is in one
session, killed at the end even on failure. Checks, on the shipped examples:
joints' peak speed and acceleration within 100.1 % of ``[JOINT_n]``, forward
kinematics in LinuxCNC agreeing with the package's, and the cycle time against
the time-optimal plan (printed).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
import uuid
from pathlib import Path

import numpy as np
import pytest
from controller._support import halcompile, require, rtapi_env, run_session, unavailable

from orthoglide_pin.controller import certify_limits, configuration_files
from orthoglide_pin.kinematics.closed_form import direct_kinematics, inverse_kinematics
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.shipped import EXAMPLE_PROGRAMS, example_program_text
from orthoglide_pin.program.axes import design_axes

pytestmark = pytest.mark.slow

#: The sliders' limits of the run [m/s], [m/s^2].
SLIDER_SPEED, SLIDER_ACCELERATION = 1.2, 20.0
#: Allowed peak use of a joint limit.
PEAK_USE = 1.001
#: Agreement of LinuxCNC's kinematics with the package's [mm].
TOL_MM = 1e-9
#: Share of status polls allowed to pair joints and pose of different servo periods.
TORN_SHARE = 1e-3
#: The sampler's resolution (6 decimals) [mm].
SAMPLE_TOL_MM = 1e-6
#: Where LinuxCNC's run ends against the plan's end [m].
END_TOL = 1e-9
#: Servo period of the configuration [s].
PERIOD = 1e-3
UI = Path(__file__).with_name("linuxcnc_ui.py")
SAMPLER_HAL = """
loadrt sampler depth=20000 cfg=fff
addf sampler.0 servo-thread
setp sampler.0.enable 0
net j0-pos => sampler.0.pin.0
net j1-pos => sampler.0.pin.1
net j2-pos => sampler.0.pin.2
"""


#: A fast program across the cube (program coordinates [mm], feed 60 m/min): the
#: certified limits bind here, where the sliders' own would allow more.
DIAGONALS = """G21 G90 G17 G64 P0.01
G1 X-72 Y-72 Z72 F60000
G1 X125 Y125 Z-125
G1 X-72 Y-72 Z72
G1 X125 Y-72 Z-125
G1 X-72 Y125 Z72
G1 X0 Y0 Z0
M2
"""
PROGRAMS = (*EXAMPLE_PROGRAMS, "diagonals")


def _program(name: str) -> str:
    if name == "diagonals":
        return DIAGONALS
    lines = [x for x in example_program_text(name).splitlines() if x.strip() != "%"]
    return "\n".join([*lines, "M2", ""])


#: The designs run: name -> (parameters, programs).
DESIGNS = {
    "prototype": (OrthoglideParams(), PROGRAMS),
    # program X on +e3, Y on +e2, Z on -e1: a rotation that keeps the diagonals in the cube
    "long-legs": (OrthoglideParams(leg_length=0.4, program_axes=(3, 2, -1)), ("diagonals",)),
}
CASES = [(d, p) for d, (_, programs) in DESIGNS.items() for p in programs]
#: Where ``halcompile --install`` says it copies the module.
_INSTALLED = re.compile(r"^cp \S+\.so (\S+?)/?$", re.MULTILINE)


def _install(comp: Path) -> Path:
    """``halcompile --install``, or skip where LinuxCNC's modules folder is not writable."""
    if os.geteuid() != 0:
        unavailable("halcompile --install writes LinuxCNC's modules folder: run as root")
    done = halcompile(comp, install=True)
    match = _INSTALLED.search(done)
    assert match, done
    return Path(match.group(1)) / f"{comp.stem}.so"


def _start(folder: Path, linuxcnc: str, env: dict[str, str]) -> None:
    """Run ``linuxcnc -r orthoglide.ini`` in its own session; kill it whole at the end."""
    run_session([linuxcnc, "-r", "orthoglide.ini"], folder, env, timeout=300)


def _run_design(folder: Path, design: str, linuxcnc: str) -> dict:
    params, programs = DESIGNS[design]
    limits = certify_limits(params, SLIDER_SPEED, SLIDER_ACCELERATION)
    folder.chmod(0o777)
    files = configuration_files(params, limits, "test")
    name = f"og_kins_{uuid.uuid4().hex[:8]}"
    comp = folder / f"{name}.comp"
    comp.write_text(files["orthoglide_kins.comp"].replace("orthoglide_kins", name))
    ini = files["orthoglide.ini"].replace("KINEMATICS = orthoglide_kins", f"KINEMATICS = {name}")
    ini = ini.replace("DISPLAY = axis", f"DISPLAY = {UI}")
    (folder / "orthoglide.ini").write_text(ini)
    (folder / "orthoglide_sim.hal").write_text(files["orthoglide_sim.hal"] + SAMPLER_HAL)
    (folder / "tool.tbl").write_text(files["tool.tbl"])
    paths = []
    for example in programs:
        path = folder / f"{example}.ngc"
        path.write_text(_program(example))
        paths.append(str(path))
    sockets = Path(tempfile.mkdtemp(prefix="orthoglide-rtapi-"))  # reachable by RTAPI_UID
    sockets.chmod(0o777)
    env = rtapi_env(sockets, OG_OUT=str(folder), OG_PROGRAMS=":".join(paths))
    installed = None
    try:
        installed = _install(comp)
        _start(folder, linuxcnc, env)
    finally:
        if installed is not None:
            installed.unlink(missing_ok=True)
        shutil.rmtree(sockets, ignore_errors=True)
    error = folder / "error.txt"
    assert not error.exists(), error.read_text()
    assert (folder / "done").exists(), (folder / "log.txt").read_text()[-3000:]
    out: dict = {"params": params, "limits": limits, "programs": {}}
    for n, example in enumerate(programs):
        data = json.loads((folder / f"{n}.json").read_text())
        data["samples"] = _samples(folder / f"{n}.samples")
        out["programs"][example] = data
    return out


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Each design's configuration run in LinuxCNC, once for the module."""
    linuxcnc = require("linuxcnc", "halcompile", "halsampler")["linuxcnc"]
    return {d: _run_design(tmp_path_factory.mktemp(d), d, linuxcnc) for d in DESIGNS}


def _samples(path: Path) -> np.ndarray:
    """The sampler's rows; ``halsampler`` flags a stream begun after an earlier one's end
    with ``overrun`` on its first line (later ones would be lost samples: refused)."""
    lines = path.read_text().splitlines()
    if lines and lines[0].strip() == "overrun":
        lines = lines[1:]
    assert all("overrun" not in x for x in lines), f"{path.name}: the sampler lost samples"
    return np.array([[float(w) for w in x.split()] for x in lines])


def _moving(samples: np.ndarray) -> np.ndarray:
    """The joints' samples [m] (sample number first), from first to last motion."""
    j = 1e-3 * samples[:, 1:4]
    move = np.flatnonzero(np.abs(np.diff(j, axis=0)).max(axis=1) > 0)
    assert move.size, "no joint moved"
    return j[max(move[0] - 2, 0) : move[-1] + 3]


@pytest.mark.parametrize(("design", "example"), CASES)
def test_joints_within_their_limits(run: dict, design: str, example: str) -> None:
    data = run[design]["programs"][example]
    assert not data["errors"], data["errors"]
    n = data["samples"][:, 0]
    assert np.all(np.diff(n) == 1), "the sampler lost samples"
    j = _moving(data["samples"])
    v = np.diff(j, axis=0) / PERIOD
    a = np.diff(v, axis=0) / PERIOD
    speed, accel = np.abs(v).max(), np.abs(a).max()
    print(
        f"{design} {example}: peak joint speed {1e3 * speed:.1f} mm/s "
        f"({100 * speed / SLIDER_SPEED:.1f} %), acceleration {1e3 * accel:.0f} mm/s^2 "
        f"({100 * accel / SLIDER_ACCELERATION:.1f} %)"
    )
    assert speed <= PEAK_USE * SLIDER_SPEED
    assert accel <= PEAK_USE * SLIDER_ACCELERATION


@pytest.mark.parametrize(("design", "example"), CASES)
def test_kinematics_in_linuxcnc_agree(run: dict, design: str, example: str) -> None:
    """LinuxCNC's pose from its joints (forward) and back (inverse), against the package.

    A status poll during motion may, rarely, pair the joints of one servo
    period with the pose of another (LinuxCNC copies its status while motion
    runs): such a pose must still be the forward kinematics of the joints of a
    sampled servo period, and such pairs must stay rare.
    """
    data = run[design]["programs"][example]
    pairs = np.asarray(data["pairs"])
    joints, poses = pairs[:, 0], pairs[:, 1]
    params = run[design]["params"]
    axes, L = design_axes(params), params.leg_length
    fk = 1e3 * axes.to_program(direct_kinematics(1e-3 * joints, L, check_limits=False))
    ik = 1e3 * inverse_kinematics(axes.to_world(1e-3 * poses), L, check_limits=False)
    agree = np.maximum(np.abs(fk - poses).max(axis=1), np.abs(ik - joints).max(axis=1))
    torn = agree > TOL_MM
    assert torn.mean() <= TORN_SHARE, f"{torn.sum()} of {len(torn)} pairs disagree"
    sampled = data["samples"][:, 1:4]
    for q in ik[torn]:  # the pose of another servo period: its joints were sampled
        assert np.abs(sampled - q).max(axis=1).min() <= SAMPLE_TOL_MM
    rest_cmd, rest_actual = np.asarray(data["rests"][0])
    assert np.abs(rest_cmd - rest_actual).max() <= TOL_MM  # at rest: inverse then forward


def test_cycle_time_against_the_optimal_plan(run: dict) -> None:
    """The cost of the certified Cartesian limits against the optimal plan (printed).

    Both read the program in the design's program axes (LinuxCNC through the
    exported component, the planner as ``orthoglide plan`` does): LinuxCNC
    ends where the plan ends. Where the programmed feeds bind, both take the
    same time; across the cube at high feed the plan, which uses each slider's
    own limits, is faster.
    """
    from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
    from orthoglide_pin.machine.closed_loop import ClosedLoopModel
    from orthoglide_pin.planning.gcode import read_program
    from orthoglide_pin.planning.limits import PlanLimits
    from orthoglide_pin.planning.plan import plan_program

    limits = PlanLimits(slider_speed=SLIDER_SPEED, slider_acceleration=SLIDER_ACCELERATION)
    costs = {}
    for design, example in CASES:
        done = run[design]
        axes = design_axes(done["params"])
        dyn = ClosedLoopDynamics(ClosedLoopModel(done["params"]))
        data = done["programs"][example]
        j = _moving(data["samples"])
        linuxcnc_time = (len(j) - 5) * PERIOD
        text = DIAGONALS if example == "diagonals" else example_program_text(example)
        program = read_program(text, axes=axes)
        rest = axes.to_world(1e-3 * np.asarray(data["rests"][0][1]))
        assert np.abs(rest - program.blocks[-1].end).max() <= END_TOL
        plan = plan_program(program, dyn, limits)
        print(
            f"{design} {example}: LinuxCNC {linuxcnc_time:.3f} s, optimal plan "
            f"{plan.cycle_time:.3f} s, cost {100 * (linuxcnc_time / plan.cycle_time - 1):.1f} %"
        )
        costs[design, example] = linuxcnc_time / plan.cycle_time - 1
    assert costs["prototype", "diagonals"] > 0.0  # the certified limits bind there
    assert all(abs(c) < 1.0 for c in costs.values())
