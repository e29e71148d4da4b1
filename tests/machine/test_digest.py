"""The design digest: stable, documented, the same for equal designs, another for each change."""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

import orthoglide_pin as og
from orthoglide_pin.machine.digest import (
    DESIGN_FIELDS,
    DIGEST_QUANTUM,
    check_design,
    design_comment,
    design_digest,
    design_text,
    read_design_comment,
)

#: The prototype's digest, as documented (docs/reference/formats.md): a file
#: written by any version of the package for the prototype records this.
PROTOTYPE_DIGEST = "bf09cda97f8d037e"
#: A change every digest must see [m]: 1000 times its resolution.
VISIBLE = 1000 * DIGEST_QUANTUM
#: Float noise it must not see [m].
NOISE = 1e-15
#: Designs other than the prototype.
OTHERS = {
    "legs": {"leg_length": 0.34075},
    "given limits": {"slider_lower": -0.08, "slider_upper": 0.19},
    "tool": {"tool_offset": (0.001, -0.002, 0.15), "platform_offset": 0.045},
}


def test_the_prototype_digest_is_the_documented_text_hashed() -> None:
    assert design_digest() == design_digest(og.prototype()) == PROTOTYPE_DIGEST
    text = design_text()
    assert text.startswith("orthoglide-design-1;leg_length=310000000;")
    assert hashlib.sha256(text.encode()).hexdigest()[:16] == PROTOTYPE_DIGEST
    assert [item.split("=")[0] for item in text.split(";")[1:]] == list(DESIGN_FIELDS)
    assert og.design_digest is design_digest and og.DESIGN_FIELDS == DESIGN_FIELDS
    formats = Path(__file__).resolve().parents[2] / "docs" / "reference" / "formats.md"
    documented = " ".join(formats.read_text().split())
    assert f"the prototype's is `{PROTOTYPE_DIGEST}`" in documented
    rule = documented.split("`orthoglide-design-1;", 1)[1].split("`", 1)[0]
    assert [item.split("=")[0] for item in rule.split(";")] == list(DESIGN_FIELDS)


@pytest.mark.parametrize("changes", list(OTHERS.values()), ids=list(OTHERS))
def test_a_yaml_round_trip_keeps_the_digest(changes: dict[str, object], tmp_path: Path) -> None:
    params = og.prototype().replace(**changes)
    back = og.OrthoglideParams.from_yaml(params.to_yaml())
    assert design_digest(back) == design_digest(params) != PROTOTYPE_DIGEST
    path = params.save(tmp_path / "design.yaml")
    assert design_digest(og.OrthoglideParams.load(path)) == design_digest(params)


@pytest.mark.parametrize("name", DESIGN_FIELDS)
def test_every_design_field_changes_the_digest(name: str) -> None:
    base = og.prototype()
    value = getattr(base, name)
    if name == "slider_lower":
        changed = base.replace(slider_lower=value - VISIBLE)
    elif name == "slider_upper":
        changed = base.replace(slider_upper=value + VISIBLE)
    elif isinstance(value, tuple):
        changed = base.replace(**{name: (value[0] + VISIBLE, *value[1:])})
    else:
        changed = base.replace(**{name: value + VISIBLE})
    assert design_digest(changed) != PROTOTYPE_DIGEST


def test_equal_designs_have_equal_digests() -> None:
    base = og.prototype()
    given = base.replace(slider_lower=base.slider_lower, slider_upper=base.slider_upper)
    assert given.derived_limits == () and design_digest(given) == PROTOTYPE_DIGEST
    assert design_digest(base.replace(leg_length=base.leg_length + NOISE)) == PROTOTYPE_DIGEST
    others = base.replace(spindle_mass=5.0, density=7800.0, bar_radius=0.012, psi_max=2.5,
                          youngs_modulus=2.1e11, actuator_stiffness=3e8)  # fmt: skip
    assert design_digest(others) == PROTOTYPE_DIGEST  # the drawing, masses, stiffness: not design


def test_check_design_names_both_designs() -> None:
    other = og.prototype().replace(leg_length=0.34075)
    theirs = design_digest(other)
    check_design(theirs, other, "cal.yaml")  # its own design: accepted
    with pytest.raises(og.DesignMismatchError) as info:
        check_design(theirs, None, "cal.yaml", leg_length=0.34075)
    message = str(info.value)
    assert "\n" not in message and theirs in message and PROTOTYPE_DIGEST in message
    assert "340.75 mm" in message and "310 mm" in message and message.startswith("cal.yaml ")
    err = info.value
    assert (err.what, err.recorded, err.expected, err.value) == (
        "cal.yaml", theirs, PROTOTYPE_DIGEST, theirs
    )  # fmt: skip
    assert isinstance(err, og.OrthoglideError) and isinstance(err, ValueError)
    tool = og.prototype().replace(tool_offset=(0.0, 0.0, 0.1))
    with pytest.raises(og.DesignMismatchError, match="the same leg length 310 mm"):
        check_design(PROTOTYPE_DIGEST, tool, "cal.yaml", leg_length=0.31)


def test_a_file_without_a_design_gets_the_line_to_add() -> None:
    with pytest.raises(og.DesignMismatchError, match=f'add the line design: "{PROTOTYPE_DIGEST}"'):
        check_design(None, None, "old.yaml")
    with pytest.raises(og.DesignMismatchError, match=r"another design \(leg length 340.75 mm\)"):
        check_design(None, None, "old.yaml", leg_length=0.34075)


def test_the_csv_design_line_round_trips() -> None:
    other = og.prototype().replace(leg_length=0.34075)
    line = design_comment(other)
    assert line == f"# orthoglide design: {design_digest(other)}, leg_length: 0.34075\n"
    assert read_design_comment(line, "w") == (design_digest(other), 0.34075)
    assert read_design_comment(f"# orthoglide design: {PROTOTYPE_DIGEST}", "w") == (
        PROTOTYPE_DIGEST, None
    )  # fmt: skip
    assert read_design_comment("t,x,y,z,path_speed", "w") is None
    for bad in ("# orthoglide design: XYZ", "# orthoglide design: 0123, leg_length: 1"):
        with pytest.raises(og.InvalidParameterError, match="design digest"):
            read_design_comment(bad, "w")
    for leg in ("-0.3", "nan", "1e400", "0.3m"):
        with pytest.raises(og.InvalidParameterError, match="leg length in metres"):
            read_design_comment(f"# orthoglide design: {PROTOTYPE_DIGEST}, leg_length: {leg}", "w")


def test_a_path_with_a_new_line_stays_on_one_line() -> None:
    with pytest.raises(og.DesignMismatchError) as info:
        check_design(None, None, "a\nb.yaml")
    assert "\n" not in str(info.value) and "'a\\nb.yaml'" in str(info.value)
