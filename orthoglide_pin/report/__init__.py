"""The torque-requirement report: its numbers, its figures and its files.

* :mod:`~orthoglide_pin.report.assemble`: every number of the report
  (:class:`ReportData`, :func:`assemble_report`);
* :mod:`~orthoglide_pin.report.program`: a part program's demand on the motors
  and its verdict rows (:class:`ProgramSection`, ``report --program``);
* :mod:`~orthoglide_pin.report.accuracy`: the part's accuracy under a cut file
  (:class:`AccuracySection`, ``report --cut``): surface error, error budget and
  the stability margin of every program line that cuts, or the lobes at home, Q1 and Q2;
* :mod:`~orthoglide_pin.report.vibration`: the lowest natural frequency over the
  cube and its verdict row (``report --min-frequency``);
* :mod:`~orthoglide_pin.report.verdict`: the verdict's rows and margins;
* :mod:`~orthoglide_pin.report.figures`: the PNG figures;
* :mod:`~orthoglide_pin.report.html`: the self-contained HTML page;
* :mod:`~orthoglide_pin.report.files`: JSON, CSV and the atomic write of the
  report directory (:func:`write_report`).

The modules import Pinocchio and matplotlib: they are loaded on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from orthoglide_pin._lazy import lazy_exports

if TYPE_CHECKING:
    from orthoglide_pin.report.accuracy import AccuracySection
    from orthoglide_pin.report.assemble import ReportData, assemble_report
    from orthoglide_pin.report.files import ReportFiles, write_report
    from orthoglide_pin.report.program import ProgramSection

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "AccuracySection": "orthoglide_pin.report.accuracy",
        "ReportData": "orthoglide_pin.report.assemble",
        "assemble_report": "orthoglide_pin.report.assemble",
        "ReportFiles": "orthoglide_pin.report.files",
        "write_report": "orthoglide_pin.report.files",
        "ProgramSection": "orthoglide_pin.report.program",
    },
    globals(),
)

__all__ = [
    "AccuracySection",
    "ProgramSection",
    "ReportData",
    "ReportFiles",
    "assemble_report",
    "write_report",
]
