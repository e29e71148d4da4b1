"""The ``drive`` command: the shipped example drive file, and the check of a drive file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import run, run_json

import orthoglide_pin as og


def test_example_prints_the_shipped_file(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    code, out, err = run(capsys, "drive", "--example")
    assert (code, err) == (0, "")
    assert out == og.example_drive_text()  # comments included, byte for byte
    saved = tmp_path / "drive.yaml"
    saved.write_text(out)  # `orthoglide drive --example > drive.yaml`
    assert og.load_drive(saved) == og.load_drive(str(og.example_drive_file()))
    data = run_json(capsys, "drive", "--example", "prototype")
    assert data["text"] == out and Path(data["path"]).is_file()


def test_check_reads_a_file_as_report_does(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    data = run_json(capsys, "drive", "--check", str(og.example_drive_file()))
    assert data["motor"]["peak_torque"] == 3.8 and data["drive_train"]["lead"] == 0.025
    assert json.loads(json.dumps(data)) == data
    code, out, _ = run(capsys, "drive", "--check", str(og.example_drive_file()))
    assert code == 0 and "rotor inertia 0.00012 kg.m^2" in out and "peak torque 3.8 N.m" in out
    train_only = tmp_path / "train.yaml"
    train_only.write_text("drive_train: {lead: 0.02}\n")
    code, out, _ = run(capsys, "drive", "--check", str(train_only))
    assert code == 0 and "lead 20 mm/rev" in out and "no motor data" in out
    alone = tmp_path / "alone.yaml"
    alone.write_text("motor: {peak_torque: 4}\n")
    code, out, err = run(capsys, "drive", "--check", str(alone))
    assert (code, out) == (2, "") and "rotor_inertia" in err and err.count("\n") == 1


def test_drive_needs_one_action(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(capsys, "drive")[0] == 2
    assert run(capsys, "drive", "--example", "nope")[0] == 2
