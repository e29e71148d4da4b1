"""Fixtures of the elasticity tests."""

from __future__ import annotations

import pytest

import orthoglide_pin as og


@pytest.fixture(scope="module")
def drive() -> og.Drive:
    """The shipped example drive."""
    return og.load_drive(str(og.example_drive_file()))
