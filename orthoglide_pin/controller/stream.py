"""The optimal route: a plan streamed to the joints at the servo rate, without LinuxCNC's planner.

The time-optimal plan (:func:`~orthoglide_pin.planning.plan.plan_program`, in
the sliders' space) is sampled every servo period and written as a
``halstreamer`` file (one line per period, the three slider positions in mm,
:func:`stream_text`). ``orthoglide_stream.hal`` (:func:`stream_hal_text`) plays
it with HAL's ``streamer`` on a servo thread of the same period, ``halrun -f
orthoglide_stream.hal``: on a simulated machine its pins are the positions;
on a real one they are wired to the drives' position commands instead of
``joint.N.motor-pos-cmd``. In a LinuxCNC session, the configuration's
``orthoglide_sim.hal`` carries a ``streamer`` of its own: with the machine
off, ``halstreamer plan.stream`` hands it the joints while it plays
(:func:`~orthoglide_pin.controller.configuration.hal_text`). No Cartesian
planner runs: the sliders follow the plan, within its limits, at its cycle
time. :func:`stream_files` gives both files (``orthoglide plan PROGRAM
--linuxcnc DIR`` and ``orthoglide linuxcnc --program PROGRAM`` write them).
The plan is whatever the planning layer made: the program read in the
design's program axes
(:func:`~orthoglide_pin.program.axes.design_axes`), as the exported
kinematics component reads the same program in LinuxCNC, so both routes cut
the same part.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import NDArray

from orthoglide_pin.dynamics.inverse import ClosedLoopDynamics
from orthoglide_pin.planning.plan import Plan
from orthoglide_pin.planning.sampling import sample_plan

FloatArray = NDArray[np.float64]

#: The stream file and its HAL file.
STREAM_FILES: Final[tuple[str, ...]] = ("plan.stream", "orthoglide_stream.hal")
#: Servo period of the stream [s] (the configuration's).
STREAM_PERIOD: Final[float] = 1e-3


def stream_columns(plan: Plan, dyn: ClosedLoopDynamics) -> dict[str, FloatArray]:
    """The plan every servo period (the columns of ``sample_plan``, planning layer)."""
    return sample_plan(plan, dyn, STREAM_PERIOD)


def stream_text(columns: dict[str, FloatArray]) -> str:
    """The ``halstreamer`` file: per servo period, slider positions ``q1 q2 q3`` [mm]."""
    q = 1e3 * np.stack([columns["q1"], columns["q2"], columns["q3"]], axis=1)
    return "".join(f"{a:.9f} {b:.9f} {c:.9f}\n" for a, b, c in q)


def stream_hal_text(samples: int) -> str:
    """The HAL file that plays ``plan.stream`` (``samples`` lines) on a servo thread."""
    nets = "\n".join(f"net q{n} streamer.0.pin.{n}" for n in range(3))
    return f"""# Plays the time-optimal plan (plan.stream, {samples} servo periods of
# {STREAM_PERIOD * 1e3:g} ms): halrun -f orthoglide_stream.hal
# The signals q0, q1, q2 are the sliders' positions [mm]: on a real machine, wire
# them to the drives' position commands (instead of joint.N.motor-pos-cmd).
loadrt threads name1=servo-thread period1={round(STREAM_PERIOD * 1e9)}
loadrt streamer depth=4096 cfg=fff
{nets}
addf streamer.0 servo-thread
start
loadusr -w halstreamer plan.stream
"""


def stream_files(plan: Plan, dyn: ClosedLoopDynamics) -> dict[str, str]:
    """Both files of the optimal route, name -> text (:data:`STREAM_FILES`)."""
    columns = stream_columns(plan, dyn)
    return {
        STREAM_FILES[0]: stream_text(columns),
        STREAM_FILES[1]: stream_hal_text(len(columns["t"])),
    }
