"""Semi-discretization on the classic single-degree-of-freedom milling benchmark.

The benchmark (Insperger and Stepan, Int. J. Numer. Meth. Eng. 61 (2004)
117-141, and the many methods compared on it since, e.g. Ding et al., Int. J.
Mach. Tools Manuf. 50 (2010) 502-509): two teeth, a mode of 922 Hz along the
feed with damping 0.011 and modal mass 0.03993 kg, K_t = 6e8 N/m^2, K_n = 2e8
N/m^2, spindle speeds 5,000-25,000 rpm, down milling at radial immersions 0.05
and 1 (the published charts span 0-10 mm of axial depth).

Checks:

* at full immersion the zero-order limit has a closed form (Altintas and
  Budak 1995): the mean directional factor along the feed is ``N K_n / 4`` and
  the lowest point of the lobes ``a = 2 k zeta (1 + zeta) / (N K_n / 4)``
  (0.298 mm here);
* at radial immersion 0.05 the charts show a period-doubling (flip) lobe the
  zero-order solution misses (Insperger and Stepan 2004; Huang and Yuan,
  Manufacturing Technology 15 (2015) 136-143: "an additional set of lobes
  corresponding to ... period doubling ... predicted only by the SD method"),
  centred where twice the tooth period holds three periods of the mode,
  ``Omega = 2 f_n / (3 N)`` (18,440 rpm): our lowest limit between 15,000
  and 22,000 rpm lies there, under half the zero-order one;
* the default discretization against a fine one (48 intervals over the cut);
* a symmetric two-degree-of-freedom tool with four teeth in a slot, where
  the directional factors hardly vary: semi-discretization and the
  zero-order solution agree.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import orthoglide_pin as og
from orthoglide_pin.machining.frf import ModalModel
from orthoglide_pin.machining.regeneration import MillingProcess
from orthoglide_pin.machining.stability_sd import critical_depths_sd, spectral_radius_sd
from orthoglide_pin.machining.stability_zoa import critical_depths_zoa

RPM = 2.0 * math.pi / 60.0
F_N, ZETA, MASS, KT, KN, TEETH = 922.0, 0.011, 0.03993, 6e8, 2e8, 2
BENCHMARK = ModalModel(
    np.array([F_N]), np.array([ZETA]), np.array([MASS]), np.array([[1.0], [0.0]])
)
#: The zero-order lobes' lowest point against its closed form, relative
#: (the chatter frequencies are sampled, 0.08 % apart).
ZOA_CLOSED_FORM_TOL = 2e-3
#: The default discretization against 48 intervals over the cut: the median
#: over the speeds, and the lowest limit, relative.
CONVERGENCE_MEDIAN_TOL = 5e-3
CONVERGENCE_MIN_TOL = 1e-2
#: Where the flip lobe's lowest point lies, relative to 2 f_n / (3 N): the
#: cut lowers the vibration's frequency a little.
FLIP_SPEED_TOL = 0.05
#: Semi-discretization (24 intervals) against the zero-order solution where
#: the latter is near exact (symmetric tool, four teeth, slot), relative, at
#: every speed.
FULL_IMMERSION_TOL = 0.015


def _process(immersion: float, teeth: int = TEETH) -> MillingProcess:
    return MillingProcess(teeth, KT, KN, math.acos(2.0 * immersion - 1.0), math.pi)


def test_zero_order_closed_form_at_full_immersion() -> None:
    k = MASS * (2.0 * math.pi * F_N) ** 2
    expected = 2.0 * k * ZETA * (1.0 + ZETA) / (TEETH * KN / 4.0)
    speeds = np.linspace(15000.0, 17000.0, 401) * RPM  # around the lowest lobe
    lowest = float(np.min(critical_depths_zoa(BENCHMARK, _process(1.0), speeds)))
    assert lowest == pytest.approx(expected, rel=ZOA_CLOSED_FORM_TOL)
    assert expected == pytest.approx(2.98e-4, rel=1e-2)


def test_convergence_in_the_intervals() -> None:
    speeds = np.linspace(5000.0, 25000.0, 41) * RPM
    coarse = critical_depths_sd(BENCHMARK, _process(0.05), speeds)
    fine = critical_depths_sd(BENCHMARK, _process(0.05), speeds, steps=48)
    assert float(np.median(np.abs(coarse / fine - 1.0))) < CONVERGENCE_MEDIAN_TOL
    assert coarse.min() == pytest.approx(fine.min(), rel=CONVERGENCE_MIN_TOL)


def test_flip_lobe_at_small_immersion() -> None:
    speeds = np.linspace(15000.0, 22000.0, 29) * RPM
    sd = critical_depths_sd(BENCHMARK, _process(0.05), speeds)
    zoa = critical_depths_zoa(BENCHMARK, _process(0.05), speeds)
    low = int(np.argmin(sd))
    expected = 2.0 * F_N / (3.0 * TEETH) * 2.0 * math.pi  # [rad/s]
    assert speeds[low] == pytest.approx(expected, rel=FLIP_SPEED_TOL)
    assert sd[low] < 0.5 * zoa[low]
    assert 1e-3 < sd[low] < 1.6e-3  # within the published chart's 0-10 mm (1.30 mm here)


def test_agrees_with_zero_order_in_a_slot() -> None:
    sym = ModalModel(np.full(2, F_N), np.full(2, ZETA), np.full(2, MASS), np.eye(2))
    speeds = np.linspace(5000.0, 25000.0, 21) * RPM
    process = _process(1.0, teeth=4)
    sd = critical_depths_sd(sym, process, speeds, steps=24)
    zoa = critical_depths_zoa(sym, process, speeds)
    assert np.allclose(sd, zoa, rtol=FULL_IMMERSION_TOL)


def test_no_cut_is_stable_and_radius_grows_with_depth() -> None:
    speeds = np.full(3, 12000.0 * RPM)
    rho = spectral_radius_sd(BENCHMARK, _process(0.5), speeds, [1e-9, 1e-3, 1e-2])
    assert rho[0] < 1.0 < rho[2]
    assert np.all(np.diff(rho) > 0.0)


def test_one_model_per_speed() -> None:
    speeds = np.array([10000.0, 20000.0]) * RPM
    stiff = ModalModel(
        np.array([F_N]), np.array([ZETA]), np.array([4 * MASS]), np.array([[1.0], [0.0]])
    )
    both = critical_depths_sd([BENCHMARK, stiff], _process(0.5), speeds)
    alone = [
        critical_depths_sd(m, _process(0.5), speeds[i : i + 1])[0]
        for i, m in enumerate([BENCHMARK, stiff])
    ]
    assert np.allclose(both, alone, rtol=1e-9)


def test_bad_process_is_refused() -> None:
    with pytest.raises(og.InvalidParameterError, match="immersion"):
        MillingProcess(2, KT, KN, 2.0, 1.0)
    with pytest.raises(og.InvalidParameterError, match="teeth"):
        MillingProcess(0, KT, KN, 0.0, 1.0)
    with pytest.raises(og.InvalidParameterError, match="depth_range"):
        critical_depths_sd(BENCHMARK, _process(0.5), [1000.0], depth_range=(1e-3, 1e-4))
