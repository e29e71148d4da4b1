"""The example drive files ship with the package and read as drives."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

import orthoglide_pin as og
from orthoglide_pin.drives.shipped import EXAMPLE_DRIVES, example_drive_file, example_drive_text


def test_the_prototype_example_is_a_complete_drive(tmp_path: Path) -> None:
    path = Path(str(example_drive_file()))
    assert path.is_file() and path.parent.name == "examples"
    text = example_drive_text()
    assert text == path.read_text()
    copy = tmp_path / "drive.yaml"
    copy.write_text(text)  # what `orthoglide drive --example > drive.yaml` does
    drive = og.load_drive(copy)
    assert drive.motor is not None and drive.motor.peak_torque == 3.8
    assert drive.train.lead == 0.025 and drive.train.rotor_inertia == 1.2e-4
    # every section is given in full: nothing in it is the silent default
    data = yaml.safe_load(text)
    assert set(data) == {"drive_train", "motor"}
    assert "rotor_inertia" in data["drive_train"] and "lead" in data["drive_train"]


def test_every_example_reads_and_unknown_names_are_refused() -> None:
    for name in EXAMPLE_DRIVES:
        assert og.load_drive(str(example_drive_file(name))).train is not None
    with pytest.raises(og.InvalidParameterError, match="prototype"):
        example_drive_text("no_such_drive")
