"""Parameter sweeps: a grid of designs evaluated in parallel, as one tidy table.

* :mod:`~orthoglide_pin.sweep.spec`: the sweep's axes, modes and settings
  (:class:`SweepSpec`) and its table of designs;
* :mod:`~orthoglide_pin.sweep.metrics`: the metrics of one design (with a
  program, :mod:`~orthoglide_pin.sweep.program`; with a cut file as well,
  :mod:`~orthoglide_pin.sweep.accuracy`: surface error and stability margin);
* :mod:`~orthoglide_pin.sweep.runner`: local processes, any executor or a Dask
  cluster, parts written atomically and resumable (:func:`run_sweep`);
* :mod:`~orthoglide_pin.sweep.store`: the sweep's directory, what counts as an
  earlier sweep of the same spec and which parts are complete;
* :mod:`~orthoglide_pin.sweep.plots`: the sweep's figures, its base design marked,
  in the units of :mod:`~orthoglide_pin.sweep.labels` (mm, N/um, um).
"""

from __future__ import annotations

from orthoglide_pin.sweep.metrics import evaluate_design, footprint
from orthoglide_pin.sweep.plots import plot_sweep, sweep_figure
from orthoglide_pin.sweep.runner import SweepResult, run_sweep
from orthoglide_pin.sweep.spec import SweepAxis, SweepSpec
from orthoglide_pin.sweep.table import sweep_table

__all__ = [
    "SweepAxis",
    "SweepResult",
    "SweepSpec",
    "evaluate_design",
    "footprint",
    "plot_sweep",
    "run_sweep",
    "sweep_figure",
    "sweep_table",
]
