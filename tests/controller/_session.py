"""The exported configuration run headless in LinuxCNC, both routes, once per test run.

For each design of :data:`DESIGNS`: every program is planned by the package
(the optimal plan, in the design's program axes); the plans of the streamed
programs are written as ``halstreamer`` files; the configuration is exported,
its component built and installed under a name of its own (``halcompile
--install``: LinuxCNC 2.9 loads modules from its own folder only; removed at
the end) and ``linuxcnc -r orthoglide.ini`` runs with the display program
``linuxcnc_ui.py`` (system Python, ``linuxcnc`` module) and a HAL ``sampler``
on the servo thread. The display plays the streams (the optimal route, through
the configuration's own streamer and its ``orthoglide_play.py``), has it
refuse a stream that starts elsewhere, then runs the programs (the certified
route). As root, ``RTAPI_UID`` is an ordinary user and ``RTAPI_FIFO_PATH`` a
socket in a folder it can write. Every process started (LinuxCNC, its
``rtapi_app``, ``milltask``, ``io``, ``halsampler``, ``halstreamer``) is in one
session, killed at the end even on failure.
"""

from __future__ import annotations

import configparser
import json
import math
import os
import re
import shutil
import tempfile
import time
import uuid
from pathlib import Path
from typing import Any

import numpy as np
from controller._support import halcompile, rtapi_env, run_session, unavailable

from orthoglide_pin.controller import certify_limits, configuration_files
from orthoglide_pin.controller.configuration import axis_limits
from orthoglide_pin.controller.player import PLAYER
from orthoglide_pin.controller.stream import stream_columns, stream_text
from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.machine.closed_loop import ClosedLoopModel
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.planning.gcode import read_program
from orthoglide_pin.planning.limits import PlanLimits
from orthoglide_pin.planning.plan import plan_program
from orthoglide_pin.planning.shipped import EXAMPLE_PROGRAMS, example_program_text
from orthoglide_pin.program.axes import design_axes

#: The sliders' limits of the runs [m/s], [m/s^2].
SLIDER_SPEED, SLIDER_ACCELERATION = 1.2, 20.0
#: Servo period of the configuration [s].
PERIOD = 1e-3
#: Longest LinuxCNC session [s].
SESSION_TIMEOUT = 600.0
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
#: The raster: rows, short G1 blocks per row, row length, step-over, wave
#: amplitude and wavelength [mm], feed [mm/min].
RASTER_ROWS, RASTER_BLOCKS_PER_ROW = 40, 250
RASTER_LENGTH, RASTER_STEP, RASTER_AMPLITUDE, RASTER_WAVE = 100.0, 3.0, 1.0, 60.0
RASTER_FEED = 60000


def raster(params: OrthoglideParams) -> str:
    """A finishing raster of 10,041 short G1 blocks (0.4 mm) over a waved surface.

    Rows along X, centred in the design's cube (its program axes), joined by
    step-overs along Y; Z follows a wave of 1 mm. From the origin and back.
    """
    centre = [(lo + hi) / 2 for lo, hi in axis_limits(params)]
    x0 = centre[0] - RASTER_LENGTH / 2
    y0 = centre[1] - RASTER_STEP * (RASTER_ROWS - 1) / 2

    def z(x: float, y: float) -> float:
        phase = 2 * math.pi * (x - x0) / RASTER_WAVE
        return centre[2] + RASTER_AMPLITUDE * math.sin(phase) * math.cos(
            2 * math.pi * (y - y0) / (3 * RASTER_WAVE)
        )

    lines = ["G21 G90 G17 G64 P0.01", f"G1 X{x0:.4f} Y{y0:.4f} Z{z(x0, y0):.4f} F{RASTER_FEED}"]
    n = RASTER_BLOCKS_PER_ROW
    for row in range(RASTER_ROWS):
        y = y0 + row * RASTER_STEP
        xs = [x0 + RASTER_LENGTH * k / n for k in range(n + 1)]
        xs = xs[::-1] if row % 2 else xs
        if row:
            lines.append(f"G1 Y{y:.4f} Z{z(xs[0], y):.4f}")
        lines += [f"G1 X{x:.4f} Z{z(x, y):.4f}" for x in xs[1:]]
    return "\n".join([*lines, "G1 X0 Y0 Z0", "M2", ""])


#: The designs run: name -> (parameters, programs of the certified route, streamed programs).
#: A streamed program starts and ends at the origin, where the joints are homed.
DESIGNS: dict[str, tuple[OrthoglideParams, tuple[str, ...], tuple[str, ...]]] = {
    "prototype": (
        OrthoglideParams(),
        (*EXAMPLE_PROGRAMS, "diagonals", "raster"),
        ("raster", "diagonals"),
    ),
    # program X on +e3, Y on +e2, Z on -e1: a rotation that keeps the diagonals in the cube
    "long-legs": (
        OrthoglideParams(leg_length=0.4, program_axes=(3, 2, -1)),
        ("diagonals", "raster"),
        ("raster", "diagonals"),
    ),
}
CASES = [(d, p) for d, (_, programs, _) in DESIGNS.items() for p in programs]
STREAM_CASES = [(d, p) for d, (_, _, streams) in DESIGNS.items() for p in streams]
#: Where ``halcompile --install`` says it copies the module.
_INSTALLED = re.compile(r"^cp \S+\.so (\S+?)/?$", re.MULTILINE)


def program_text(name: str, params: OrthoglideParams) -> str:
    """The program ``name`` as the planner reads it."""
    if name == "diagonals":
        return DIAGONALS
    if name == "raster":
        return raster(params)
    return example_program_text(name)


def _linuxcnc_program(name: str, params: OrthoglideParams) -> str:
    """The program as LinuxCNC runs it: no ``%`` lines, ``M2`` at the end."""
    lines = [x for x in program_text(name, params).splitlines() if x.strip() != "%"]
    return "\n".join([*lines, *([] if lines[-1] == "M2" else ["M2"]), ""])


def _install(comp: Path) -> Path:
    """``halcompile --install``, or skip where LinuxCNC's modules folder is not writable."""
    if os.geteuid() != 0:
        unavailable("halcompile --install writes LinuxCNC's modules folder: run as root")
    done = halcompile(comp, install=True)
    match = _INSTALLED.search(done)
    assert match, done
    return Path(match.group(1)) / f"{comp.stem}.so"


def _plans(params: OrthoglideParams, names: set[str], streamed: tuple[str, ...]) -> dict:
    """Each program's optimal plan: its cycle time, end, and (streamed) its servo samples."""
    axes = design_axes(params)
    dyn = ClosedLoopDynamics(ClosedLoopModel(params))
    limits = PlanLimits(slider_speed=SLIDER_SPEED, slider_acceleration=SLIDER_ACCELERATION)
    plans: dict[str, dict[str, Any]] = {}
    for name in sorted(names):
        begun = time.perf_counter()
        program = read_program(program_text(name, params), axes=axes)
        plan = plan_program(program, dyn, limits)
        plans[name] = {
            "cycle_time": plan.cycle_time,
            "end": program.blocks[-1].end,
            "blocks": len(program.blocks),
            "planned_in": time.perf_counter() - begun,
        }
        if name in streamed:
            plans[name]["columns"] = stream_columns(plan, dyn)
    return plans


def _samples(path: Path) -> np.ndarray:
    """The sampler's rows; ``halsampler`` flags a stream begun after an earlier one's end
    with ``overrun`` on its first line (later ones would be lost samples: refused)."""
    lines = path.read_text().splitlines()
    if lines and lines[0].strip() == "overrun":
        lines = lines[1:]
    assert all("overrun" not in x for x in lines), f"{path.name}: the sampler lost samples"
    return np.array([[float(w) for w in x.split()] for x in lines])


def run_design(folder: Path, design: str, linuxcnc: str) -> dict:
    """Plan, export and run ``design`` in LinuxCNC, both routes; the runs' records."""
    params, programs, streams = DESIGNS[design]
    limits = certify_limits(params, SLIDER_SPEED, SLIDER_ACCELERATION)
    plans = _plans(params, set(programs) | set(streams), streams)
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
    (folder / PLAYER).write_text(files[PLAYER])
    paths = []
    for program in programs:
        path = folder / f"{program}.ngc"
        path.write_text(_linuxcnc_program(program, params))
        paths.append(str(path))
    played = []
    for program in streams:
        path = folder / f"{program}.stream"
        path.write_text(stream_text(plans[program]["columns"]))
        played.append(str(path))
    refused = folder / "elsewhere.stream"  # starts 1 mm away from where the joints are
    refused.write_text("1.0 0.0 0.0\n1.0 0.0 0.0\n")
    sockets = Path(tempfile.mkdtemp(prefix="orthoglide-rtapi-"))  # reachable by RTAPI_UID
    sockets.chmod(0o777)
    env = rtapi_env(
        sockets,
        OG_OUT=str(folder),
        OG_PROGRAMS=":".join(paths),
        OG_STREAMS=":".join(played),
        OG_REFUSED_STREAM=str(refused),
    )
    installed = None
    try:
        installed = _install(comp)
        run_session([linuxcnc, "-r", "orthoglide.ini"], folder, env, timeout=SESSION_TIMEOUT)
    finally:
        if installed is not None:
            installed.unlink(missing_ok=True)
        shutil.rmtree(sockets, ignore_errors=True)
    error = folder / "error.txt"
    assert not error.exists(), error.read_text()
    assert (folder / "done").exists(), (folder / "log.txt").read_text()[-3000:]
    ini_file = configparser.ConfigParser(interpolation=None)
    ini_file.read(folder / "orthoglide.ini")
    joints = [ini_file[f"JOINT_{n}"] for n in range(3)]
    out: dict = {
        "params": params,
        "limits": limits,
        # the [JOINT_n] limits LinuxCNC ran with [m/s], [m/s^2]
        "joint_speed": 1e-3 * min(float(j["MAX_VELOCITY"]) for j in joints),
        "joint_acceleration": 1e-3 * min(float(j["MAX_ACCELERATION"]) for j in joints),
        "plans": plans,
        "programs": {},
        "streams": {},
        "refused": json.loads((folder / "refused.json").read_text()),
    }
    for kind, names, prefix in (("programs", programs, ""), ("streams", streams, "s")):
        for n, program in enumerate(names):
            data = json.loads((folder / f"{prefix}{n}.json").read_text())
            data["samples"] = _samples(folder / f"{prefix}{n}.samples")
            out[kind][program] = data
    return out


def moving(samples: np.ndarray) -> np.ndarray:
    """The joints' samples [m] (sample number first), from first to last motion."""
    j = 1e-3 * samples[:, 1:4]
    move = np.flatnonzero(np.abs(np.diff(j, axis=0)).max(axis=1) > 0)
    assert move.size, "no joint moved"
    return j[max(move[0] - 2, 0) : move[-1] + 3]


def peaks(samples: np.ndarray) -> tuple[float, float]:
    """The joints' peak speed [m/s] and acceleration [m/s^2], every servo period."""
    assert np.all(np.diff(samples[:, 0]) == 1), "the sampler lost samples"
    j = moving(samples)
    v = np.diff(j, axis=0) / PERIOD
    a = np.diff(v, axis=0) / PERIOD
    return float(np.abs(v).max()), float(np.abs(a).max())
