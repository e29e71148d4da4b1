"""The position loop of each slider: settings, gains and the controllers.

Each slider has its own digital position loop, run at ``rate`` [Hz]: at every
period the encoder position is read (quantised to the encoder's resolution
when ``encoder_counts`` is given, the speed then a backward difference),
compared with the planned slider motion, and a motor torque is held until the
next period. The controllers (:data:`CONTROLLERS`):

* ``pid_ff``: PID on the position error, velocity feedforward (the D term acts
  on the speed error ``q'_ref - q'``) and torque feedforward from the
  closed-loop inverse dynamics and the drive (rotor inertia, friction, screw
  efficiency: :func:`~orthoglide_pin.simulation.slider_drive.feedforward_torque`);
* ``pd_ff``: the same without the integral;
* ``pd``: PD with velocity feedforward and no torque feedforward, the classic
  loop of a machine tool (gravity and inertia are left to the feedback).

The gains place the closed loop of each slider, taken as the mass ``m`` it
moves at the start point (its own, the machine's share and the rotor's), on a
triple pole ``-w`` with ``w = 2 pi rate / BANDWIDTH_DIVISOR``:
``kp = 3 m w^2``, ``kd = 3 m w``, ``ki = m w^3`` (``pid_ff``); a double pole
``kp = m w^2``, ``kd = 2 m w`` without the integral. The force the loop asks
is turned into motor torque by ``1 / (k eta)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from orthoglide_pin._validation import choice, integer, number_in, size_within
from orthoglide_pin.exceptions import InvalidParameterError

FloatArray = NDArray[np.float64]

#: The controllers: name -> what it does.
CONTROLLERS: Final = {
    "pid_ff": "PID, velocity and torque feedforward",
    "pd_ff": "PD, velocity and torque feedforward",
    "pd": "PD, velocity feedforward, no torque feedforward",
}
#: Default servo rate [Hz].
DEFAULT_RATE: Final[float] = 4000.0
#: Highest servo rate [Hz].
MAX_RATE: Final[float] = 100_000.0
#: Lowest servo rate [Hz]: the periods per second of cycle a run needs at least.
MIN_RATE: Final[float] = 500.0
#: Servo periods a run needs per block of the program that takes time, at least on
#: average (a coarser period would step over whole blocks and miss their error).
MIN_PERIODS_PER_BLOCK: Final[int] = 10
#: Most servo periods of a run held in memory (a cycle of 250 s at 4 kHz; a streamed run has none).
MAX_PERIODS: Final[int] = 1_000_000
#: The loop's bandwidth is the rate over this [-].
BANDWIDTH_DIVISOR: Final[float] = 20.0
#: Largest model error, as a fraction [-].
MAX_MODEL_ERROR: Final[float] = 0.9
#: Most encoder counts per motor revolution [-].
MAX_ENCODER_COUNTS: Final[int] = 2**32


@dataclass(frozen=True)
class ServoSettings:
    """How the sliders are controlled, and how wrong the controller's model is.

    Attributes:
        controller: One of :data:`CONTROLLERS`.
        rate: Servo rate [Hz], in ``[MIN_RATE, MAX_RATE]``.
        encoder_counts: Encoder counts per motor revolution, or ``None`` (exact positions).
        mass_error: Relative error of the controller's masses and inertias (machine
            and rotors), in ``[-MAX_MODEL_ERROR, MAX_MODEL_ERROR]`` [-].
        friction_error: Relative error of its friction, same range [-].
    """

    controller: str = "pid_ff"
    rate: float = DEFAULT_RATE
    encoder_counts: int | None = None
    mass_error: float = 0.0
    friction_error: float = 0.0

    def __post_init__(self) -> None:
        choice("controller", self.controller, CONTROLLERS)
        rate = number_in("rate", self.rate, MIN_RATE, MAX_RATE, "[Hz]")
        object.__setattr__(self, "rate", rate)
        if self.encoder_counts is not None:
            integer("encoder_counts", self.encoder_counts, 1, MAX_ENCODER_COUNTS)
        for name in ("mass_error", "friction_error"):
            value = getattr(self, name)
            try:
                number = math.nan if isinstance(value, (bool, str)) else float(value)
            except (TypeError, ValueError):
                number = math.nan
            if not (math.isfinite(number) and abs(number) <= MAX_MODEL_ERROR):
                raise InvalidParameterError(
                    name, value, f"a fraction in [-{MAX_MODEL_ERROR:g}, {MAX_MODEL_ERROR:g}]"
                )
            object.__setattr__(self, name, number)

    @property
    def period(self) -> float:
        """The servo period [s]."""
        return 1.0 / self.rate

    def check_sampling(self, cycle_time: float, blocks: int, *, capped: bool = True) -> None:
        """Refuse a rate that cannot sample a program, or would make too many periods.

        Args:
            cycle_time: The program's cycle time [s].
            blocks: Its blocks that take time (moves and dwells).
            capped: Whether the run is held in memory (at most :data:`MAX_PERIODS`
                periods); a streamed run has no limit.

        Raises:
            InvalidParameterError: Fewer than :data:`MIN_PERIODS_PER_BLOCK` periods
                per block on average (naming the rate and the lowest one allowed), or
                more than :data:`MAX_PERIODS` periods (``capped``).
        """
        periods = cycle_time * self.rate
        if blocks and periods < MIN_PERIODS_PER_BLOCK * blocks:
            lowest = MIN_PERIODS_PER_BLOCK * blocks / cycle_time
            raise InvalidParameterError(
                "rate",
                self.rate,
                f"at least {lowest:.6g} Hz for this program: {MIN_PERIODS_PER_BLOCK} servo "
                f"periods per block ({blocks} blocks in {cycle_time:.6g} s)",
            )
        if not capped:
            return
        size_within(
            "rate", self.rate, periods + 1.0, MAX_PERIODS, f"servo periods over {cycle_time:.6g} s"
        )

    @property
    def torque_feedforward(self) -> bool:
        """Whether the controller adds the torque feedforward."""
        return self.controller != "pd"


@dataclass(frozen=True)
class Gains:
    """Slider-force gains of the three loops.

    Attributes:
        kp: Position gains [N/m], (3,). kd: Speed gains [N.s/m], (3,).
        ki: Integral gains [N/(m.s)], (3,) (zero without the integral).
    """

    kp: FloatArray
    kd: FloatArray
    ki: FloatArray


def servo_gains(settings: ServoSettings, mass: ArrayLike) -> Gains:
    """The gains of the loops for the masses each slider moves [kg], shape (3,)."""
    m = np.asarray(mass, dtype=float)
    w = 2.0 * math.pi * settings.rate / BANDWIDTH_DIVISOR
    if settings.controller == "pid_ff":
        return Gains(3.0 * m * w * w, 3.0 * m * w, m * w**3)
    return Gains(m * w * w, 2.0 * m * w, np.zeros_like(m))


class Encoder:
    """The position and speed the controller reads, one slider.

    Args:
        resolution: Slider travel of one count [m], or ``None`` (exact reading).
        period: Servo period [s].
        start: Slider position at the start [m].
    """

    def __init__(self, resolution: float | None, period: float, start: float) -> None:
        self.resolution = resolution
        self.period = period
        self._last = self.quantise(start)

    def quantise(self, q: float) -> float:
        """The counted position [m]."""
        if self.resolution is None:
            return q
        return round(q / self.resolution) * self.resolution

    def read(self, q: float, qd: float) -> tuple[float, float]:
        """Position and speed read at a period: exact, or counted and differenced."""
        if self.resolution is None:
            return q, qd
        counted = self.quantise(q)
        speed = (counted - self._last) / self.period
        self._last = counted
        return counted, speed


class PositionLoop:
    """The feedback part of one slider's loop (the feedforward is added by the caller).

    Args:
        kp: Position gain [N/m]. kd: Speed gain [N.s/m]. ki: Integral gain [N/(m.s)].
        period: Servo period [s].
    """

    def __init__(self, kp: float, kd: float, ki: float, period: float) -> None:
        self.kp, self.kd, self.ki = kp, kd, ki
        self.period = period
        self.integral = 0.0

    def force(self, error: float, speed_error: float, frozen: bool) -> float:
        """Slider force asked [N] for a position and a speed error [m, m/s].

        The integral does not grow while the motor was saturated at the
        previous period (``frozen``, anti-windup).
        """
        if not frozen:
            self.integral += error * self.period
        return self.kp * error + self.kd * speed_error + self.ki * self.integral
