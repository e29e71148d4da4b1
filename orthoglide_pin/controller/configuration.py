"""A complete LinuxCNC 2.9 configuration of one design: component, INI, HAL, README.

:func:`configuration_files` returns the files (name -> text) that
``orthoglide linuxcnc --out DIR`` writes:

* ``orthoglide_kins.comp``, the kinematics (:mod:`~orthoglide_pin.controller.component`);
* ``orthoglide.ini``: ``[JOINT_n]`` limits are the sliders' (their strokes,
  speed and acceleration), ``[TRAJ]`` and ``[AXIS_*]`` limits the certified
  Cartesian ones (:mod:`~orthoglide_pin.controller.limits`), the axes' soft
  limits the cube's (in the design's program axes, those of ``orthoglide
  plan``, 1 nm inside);
* ``orthoglide_sim.hal``: a simulated machine (each joint's commanded position
  looped back as its feedback, as LinuxCNC's sim configurations do), with
  HAL's ``streamer``, whose positions the joints take while it plays a stream
  (the optimal route, :mod:`~orthoglide_pin.controller.stream`, machine off);
* ``orthoglide_play.py``: plays a stream on the running session
  (:mod:`~orthoglide_pin.controller.player`);
* ``tool.tbl`` and ``README.md`` (build, run, wiring a real machine).

Every length is in mm, as LinuxCNC reads them (``LINEAR_UNITS = mm``).
"""

from __future__ import annotations

import math
import re
from typing import Final

import numpy as np

from orthoglide_pin.controller.component import COMPONENT, component_text
from orthoglide_pin.controller.limits import CartesianLimits
from orthoglide_pin.controller.player import PLAYER, player_text
from orthoglide_pin.exceptions import InvalidParameterError
from orthoglide_pin.machine.coerce import as_params
from orthoglide_pin.machine.params import OrthoglideParams
from orthoglide_pin.program.axes import design_axes

#: The files of a configuration, in the order they are written.
FILES: Final[tuple[str, ...]] = (
    f"{COMPONENT}.comp",
    "orthoglide.ini",
    "orthoglide_sim.hal",
    PLAYER,
    "tool.tbl",
    "README.md",
)
#: Servo period of the configuration [s] (LinuxCNC's default, 1 ms).
SERVO_PERIOD: Final[float] = 1e-3
#: How far inside the cube the axes' soft limits are [mm] (rounding of the limits).
SOFT_LIMIT_INSET: Final[float] = 1e-6
#: Depth of the simulated machine's stream FIFO [servo periods] (``halstreamer`` refills it).
STREAM_DEPTH: Final[int] = 4096


def _mm(value: float) -> str:
    return f"{1e3 * value:.9f}"


def axis_limits(params: OrthoglideParams) -> list[tuple[float, float]]:
    """The cube in the design's program axes: ``(min, max)`` of X, Y, Z [mm], 1 nm inside."""
    lo = np.asarray(params.workspace_corner, dtype=float)
    corners = np.stack([lo, lo + params.workspace_side])
    prog = 1e3 * design_axes(params).to_program(corners)
    return [
        (float(prog[:, a].min()) + SOFT_LIMIT_INSET, float(prog[:, a].max()) - SOFT_LIMIT_INSET)
        for a in range(3)
    ]


def ini_text(params: OrthoglideParams, limits: CartesianLimits, digest: str) -> str:
    """The INI of the configuration (LinuxCNC 2.9, mm and s)."""
    v, a = 1e3 * limits.speed, 1e3 * limits.acceleration
    axes = []
    for name, (lo, hi) in zip("XYZ", axis_limits(params), strict=True):
        axes.append(
            f"[AXIS_{name}]\nMAX_VELOCITY = {v:.6g}\nMAX_ACCELERATION = {a:.6g}\n"
            f"MIN_LIMIT = {lo:.9f}\nMAX_LIMIT = {hi:.9f}\n"
        )
    joints = []
    for n in range(3):
        joints.append(
            f"[JOINT_{n}]\nTYPE = LINEAR\nHOME = 0.0\nHOME_OFFSET = 0.0\n"
            f"HOME_SEARCH_VEL = 0.0\nHOME_LATCH_VEL = 0.0\nHOME_SEQUENCE = 0\n"
            f"MAX_VELOCITY = {1e3 * limits.joint_speed:.9g}\n"
            f"MAX_ACCELERATION = {1e3 * limits.joint_acceleration:.9g}\n"
            f"MIN_LIMIT = {_mm(params.slider_lower)}\nMAX_LIMIT = {_mm(params.slider_upper)}\n"
            "FERROR = 1.0\nMIN_FERROR = 0.25\n"
        )
    jerk = (
        "none given"
        if limits.joint_jerk is None
        else f"{1e3 * limits.joint_jerk:.6g} mm/s^3 (not a LinuxCNC 2.9 setting)"
    )
    return f"""# LinuxCNC 2.9 configuration of an Orthoglide, written by orthoglide linuxcnc.
# Design {digest}: leg length {1e3 * params.leg_length:.6g} mm, cube of side
# {1e3 * params.workspace_side:.6g} mm. Lengths in mm, times in s.
# Program axes on the world axes (the design's, as orthoglide plan reads
# programs): {design_axes(params).describe()}.
#
# [JOINT_n]: the sliders' limits (stroke, speed, acceleration). Slider jerk: {jerk}.
# [TRAJ] and [AXIS_*]: Cartesian limits certified over the whole cube: under
# them no slider exceeds its speed or acceleration (README.md):
#   slider speed        <= {limits.speed_gain:.6f} x path speed
#                        = {1e3 * limits.worst_joint_speed():.6f} mm/s
#   slider acceleration <= {limits.acceleration_gain:.6f} x axis acceleration
#                          + {limits.curvature:.6f} /m x path speed^2
#                        = {1e3 * limits.worst_joint_acceleration():.6f} mm/s^2

[EMC]
VERSION = 1.1
MACHINE = Orthoglide {digest}
DEBUG = 0

[DISPLAY]
DISPLAY = axis
CYCLE_TIME = 0.100
POSITION_OFFSET = RELATIVE
POSITION_FEEDBACK = ACTUAL
MAX_FEED_OVERRIDE = 1.0
PROGRAM_PREFIX = .
INTRO_GRAPHIC =
INTRO_TIME = 0

[TASK]
TASK = milltask
CYCLE_TIME = 0.001

[RS274NGC]
PARAMETER_FILE = orthoglide.var

[EMCMOT]
EMCMOT = motmod
COMM_TIMEOUT = 1.0
SERVO_PERIOD = {round(SERVO_PERIOD * 1e9)}

[EMCIO]
EMCIO = io
CYCLE_TIME = 0.100
TOOL_TABLE = tool.tbl

[HAL]
HALFILE = orthoglide_sim.hal

[KINS]
KINEMATICS = {COMPONENT}
JOINTS = 3

[TRAJ]
COORDINATES = XYZ
LINEAR_UNITS = mm
ANGULAR_UNITS = degree
DEFAULT_LINEAR_VELOCITY = {v:.6g}
MAX_LINEAR_VELOCITY = {v:.6g}
DEFAULT_LINEAR_ACCELERATION = {a:.6g}
MAX_LINEAR_ACCELERATION = {a:.6g}

{chr(10).join(axes)}
{chr(10).join(joints)}"""


def hal_text() -> str:
    """The HAL file of the simulated machine (joints looped back, the stream's selectors).

    Each joint's position (signal ``jN-pos``, its feedback) is motion's
    command, except while HAL's ``streamer`` plays a stream (``halstreamer
    plan.stream``, the optimal route, with the machine off): then it is the
    stream's (``og-select-N``, a ``mux2`` switched by ``streamer.0.empty``).
    """
    joints = "\n".join(
        f"net j{n}-cmd joint.{n}.motor-pos-cmd => og-select-{n}.in1\n"
        f"net q{n} streamer.0.pin.{n} => og-select-{n}.in0\n"
        f"net j{n}-pos og-select-{n}.out => joint.{n}.motor-pos-fb"
        for n in range(3)
    )
    selects = ",".join(f"og-select-{n}" for n in range(3))
    return f"""# Simulated Orthoglide: each joint's commanded position is its feedback.
# For a real machine, replace the loops by the drives (README.md).
loadrt [KINS]KINEMATICS
loadrt [EMCMOT]EMCMOT servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS
addf motion-command-handler servo-thread
addf motion-controller servo-thread

# The optimal route (README.md): while the streamer plays a stream (machine off,
# python3 {PLAYER} plan.stream), the joints' positions are the stream's;
# otherwise motion's commands.
loadrt streamer depth={STREAM_DEPTH} cfg=fff
loadrt mux2 names={selects}
addf streamer.0 servo-thread
{chr(10).join(f"addf og-select-{n} servo-thread" for n in range(3))}
net og-stream-idle streamer.0.empty => {" ".join(f"og-select-{n}.sel" for n in range(3))}

{joints}

net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in
net tool-prep-loop iocontrol.0.tool-prepare => iocontrol.0.tool-prepared
net tool-change-loop iocontrol.0.tool-change => iocontrol.0.tool-changed
"""


def readme_text(params: OrthoglideParams, limits: CartesianLimits, digest: str) -> str:
    """The README of the configuration: build, run, the limits, a real machine."""
    (xl, xh), (yl, yh), (zl, zh) = axis_limits(params)
    r2, r1, k = limits.sampled
    return f"""# Orthoglide on LinuxCNC 2.9 (design {digest})

Written by `orthoglide linuxcnc`. Lengths in mm, times in s.

## Build the kinematics and run

    sudo apt-get install linuxcnc-uspace linuxcnc-uspace-dev   # Debian 12 and later
    sudo halcompile --install {COMPONENT}.comp
    linuxcnc orthoglide.ini

The machine starts at the isotropic configuration (every slider at 0, the
tool at the world origin); home all joints (they home where they stand), then
run programs. Program axes, the design's (`program_axes`), as `orthoglide
plan` reads programs: {design_axes(params).describe()} (ISO 841: +Z moves the
tool away from the part; the world's e3 points down). The soft limits are the
cube: X {xl:.3f} .. {xh:.3f}, Y {yl:.3f} .. {yh:.3f}, Z {zl:.3f} .. {zh:.3f}.

## The limits, and why the joints keep theirs

LinuxCNC 2.9 plans in Cartesian space and does not look at the joints' speed
and acceleration limits under a non-trivial kinematics (LinuxCNC issue #97).
The Cartesian limits of `orthoglide.ini` are chosen so that it never needs to:
over the whole cube, rigorous interval bounds (arb balls) give

* slider speed <= {limits.speed_gain:.6f} x path speed (max of L / eta_i; on a grid: {r2:.6f});
* slider acceleration <= {limits.acceleration_gain:.6f} x axis acceleration
  (max row sum of J^-1; grid: {r1:.6f}) + {limits.curvature:.6f} /m x path speed^2
  (max of L^2 / eta_i^3; grid: {k:.6f}).

With the sliders' {1e3 * limits.joint_speed:.6g} mm/s and
{1e3 * limits.joint_acceleration:.6g} mm/s^2, the path speed is
{1e3 * limits.speed:.6g} mm/s and each axis's acceleration
{1e3 * limits.acceleration:.6g} mm/s^2. The time-optimal plan in the sliders'
space (`orthoglide plan`) is faster: it uses each slider's limits where they bind.

## The optimal route: a plan streamed to the joints

`orthoglide plan PROGRAM --out PLAN --linuxcnc .` writes the time-optimal
plan here as `plan.stream` (the sliders' positions every servo period).
`orthoglide_sim.hal` carries HAL's `streamer`: while it plays, each joint's
position is the stream's (`og-select-N`, switched by `streamer.0.empty`),
otherwise motion's command. With LinuxCNC running, the joints homed and
where the stream starts (the program's start point, the origin unless the
program moves first), and no program running:

    python3 {PLAYER} plan.stream

turns the machine off, runs `halstreamer plan.stream` (the sliders follow
the plan, within its limits, at its cycle time; the display shows the tool,
motion's forward kinematics of the streamed joints), waits until the last
line has played (`streamer.0.empty`), and turns the machine on again:
LinuxCNC goes on from where the stream ended. It refuses, moving nothing, a
stream that does not start where the joints are.

The machine is off while the stream plays because LinuxCNC 2.9 has no input
through which HAL commands the joints while motion is enabled: motion owns
`joint.N.motor-pos-cmd`, and a feedback that leaves it trips a following
error. With motion disabled its command tracks the feedback, which is the
stream; LinuxCNC checks nothing of the motion meanwhile (no following error,
no soft limit): the plan, verified in the sliders' space, holds the limits.
`halrun -f orthoglide_stream.hal` plays the same file without LinuxCNC.

## A real machine

Replace the three loops of `orthoglide_sim.hal` (`og-select-N.out` to
`joint.N.motor-pos-fb`) by the drives: `og-select-N.out` (motion's command,
or the stream's while it plays) to the step generator or servo loop of
slider N+1, its encoder to `joint.N.motor-pos-fb`; the home switches and
`HOME_*` of each `[JOINT_n]` (the sliders read 0 at the isotropic
configuration); the machine's E-stop chain instead of `estop-loop`. Enable
the drives with `joint.N.amp-enable-out` or, while a stream plays (the
machine off), with `streamer.0.empty` false (an `or2`), both behind the
E-stop chain. Keep the `[JOINT_n]` limits those of the drives: the
Cartesian limits are certified against them, and the stream is planned
within them.
"""


def configuration_files(
    params: OrthoglideParams | None, limits: CartesianLimits, digest: str, source: str = ""
) -> dict[str, str]:
    """The files of the configuration, name -> text (see :data:`FILES`).

    Args:
        params: The design; ``None``: the prototype.
        limits: Its certified limits (:func:`~orthoglide_pin.controller.limits.certify_limits`).
        digest: The design digest, recorded in the files (letters, digits, ``_``, ``-``).
        source: Where the design comes from, one line for the component's description.

    Raises:
        InvalidParameterError: A wrong kind of argument, or limits without a
            positive acceleration (the sliders' acceleration is spent on speed).
    """
    params = as_params(params)
    if not isinstance(limits, CartesianLimits):
        raise InvalidParameterError("limits", limits, "CartesianLimits (certify_limits)")
    if not isinstance(digest, str) or not re.fullmatch(r"[0-9A-Za-z_-]{1,64}", digest):
        raise InvalidParameterError("digest", digest, "a design digest (letters, digits, _ -)")
    if not isinstance(source, str) or len(source) > 200 or not source.isprintable():
        raise InvalidParameterError("source", source, "one printable line of text")
    if not math.isfinite(limits.speed) or limits.acceleration <= 0.0:
        raise InvalidParameterError(
            "acceleration", limits.acceleration, "positive: raise the slider acceleration"
        )
    return {
        f"{COMPONENT}.comp": component_text(params, source),
        "orthoglide.ini": ini_text(params, limits, digest),
        "orthoglide_sim.hal": hal_text(),
        PLAYER: player_text(),
        "tool.tbl": "T1 P1 Z0.0 D0.0 ;\n",
        "README.md": readme_text(params, limits, digest),
    }
