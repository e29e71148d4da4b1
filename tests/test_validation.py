"""The shared argument checks (orthoglide_pin._validation): what each accepts and refuses."""

from __future__ import annotations

import math
from collections import OrderedDict
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from orthoglide_pin._validation import (
    MAX_GRAVITY,
    bounded_vector,
    capped_points,
    choice,
    finite_number,
    flag,
    gravity_vector,
    integer,
    mapping,
    mappings,
    name_list,
    number_in,
    optional_callable,
    path_argument,
    positive_limit,
    size_within,
    text,
)
from orthoglide_pin.exceptions import InvalidParameterError

#: Values of the wrong kind for every check below.
WRONG: tuple[Any, ...] = (None, "abc", {"a": 1}, np.zeros((4, 5)), object())


def _refused(check: Any, value: Any, *args: Any) -> InvalidParameterError:
    with pytest.raises(InvalidParameterError) as info:
        check("arg", value, *args)
    assert info.value.name == "arg" and str(info.value).startswith("invalid arg=")
    assert "\n" not in str(info.value)
    return info.value


def test_flag_is_a_bool_and_nothing_else() -> None:
    assert flag("arg", True) is True and flag("arg", np.bool_(False)) is False
    for bad in (*WRONG, 0, 1, 1.0, "True"):
        assert "True or False" in str(_refused(flag, bad))


def test_integer_in_its_range() -> None:
    assert integer("arg", 3) == 3 and integer("arg", np.int64(7), 2, 7) == 7
    assert type(integer("arg", np.int32(4))) is int
    for bad in (*WRONG, True, 2.0, math.nan, 0, -1):
        _refused(integer, bad)
    assert "[2, 5]" in str(_refused(integer, 6, 2, 5))
    assert ">= 2" in str(_refused(integer, 1, 2))


def test_finite_number_of_any_sign() -> None:
    assert finite_number("arg", -2) == -2.0 and finite_number("arg", np.float32(0.5)) == 0.5
    for bad in (*WRONG, True, math.nan, math.inf, np.zeros(2)):
        _refused(finite_number, bad)
    assert "[rad]" in str(_refused(finite_number, math.inf, "[rad]"))


def test_positive_limit_admits_infinity() -> None:
    assert positive_limit("arg", math.inf) == math.inf and positive_limit("arg", 1e6) == 1e6
    for bad in (*WRONG, True, math.nan, 0.0, -1.0):
        _refused(positive_limit, bad)


def test_choice_lists_the_choices_quoted() -> None:
    assert choice("arg", "y", ("x", "y")) == "y"
    for bad in (*WRONG, "z", np.array(["x"])):
        assert "one of 'x', 'y'" in str(_refused(choice, bad, ("x", "y")))


def test_text_path_and_mappings() -> None:
    assert text("arg", "a") == "a"
    path = Path("a")
    assert path_argument("arg", path) is path and path_argument("arg", "a") == "a"
    assert "not ndarray" in str(_refused(path_argument, np.zeros(3)))
    ordered = OrderedDict(a=1)
    assert mapping("arg", ordered) is ordered
    assert mappings("arg", [ordered, {"b": 2}]) == [ordered, {"b": 2}]
    for bad in WRONG:
        if not isinstance(bad, str):
            _refused(text, bad)
            _refused(path_argument, bad)
        if not isinstance(bad, dict):
            _refused(mapping, bad)
    for bad in (*WRONG, [1], ({"a": 1}, "b")):
        _refused(mappings, bad)


def test_name_list_takes_one_name_or_several() -> None:
    assert name_list("arg", "x") == ("x",) and name_list("arg", ["x", "y"]) == ("x", "y")
    assert name_list("arg", ()) == ()
    for bad in (*WRONG[:1], *WRONG[2:], ["x", 1]):
        _refused(name_list, bad)


def test_optional_callable() -> None:
    assert optional_callable("arg", None) is None and optional_callable("arg", len) is len
    for bad in (*WRONG[1:], 3):
        assert "not " in str(_refused(optional_callable, bad))


def test_bounded_vector_names_the_range() -> None:
    assert bounded_vector("origin", [1.0, -1000.0, 0.0], 3, 1e3, "[m]").tolist() == [1, -1000, 0]
    for bad in ((1e300, 0, 0), (0, 0, -1000.5), (math.inf, 0, 0), (1, 2)):
        error = _refused(bounded_vector, bad, 3, 1e3, "[m]")
        assert "3 " in error.allowed and "[m]" in error.allowed


def test_gravity_vector_caps_the_magnitude() -> None:
    assert gravity_vector((0, 0, 9.81)).tolist() == [0, 0, 9.81]
    for bad in ((1e300, 0, 0), (800, 800, 0), (math.nan, 0, 0), (0, 0)):
        _refused(lambda name, value: gravity_vector(value, name), bad)
    error = _refused(lambda name, value: gravity_vector(value, name), (0, 0, MAX_GRAVITY + 1))
    assert f"magnitude at most {MAX_GRAVITY:g} m/s^2" in str(error)


def test_number_in_takes_the_closed_range_only() -> None:
    assert number_in("dt", 1e-6, 1e-6, 0.1, "[s]") == 1e-6
    assert number_in("dt", np.float32(0.05), 1e-6, 0.1, "[s]") == pytest.approx(0.05)
    for bad in (*WRONG, 0.0, 0.2, math.nan, math.inf, 10**400, True, "0.01"):
        assert "[1e-06, 0.1] [s]" in str(_refused(number_in, bad, 1e-6, 0.1, "[s]"))


def test_size_within_names_the_cap_and_the_size() -> None:
    size_within("step", 1e-3, 5e6, 5_000_000, "points")
    for count, shown in ((5e6 + 1, "5,000,001"), (1e20, "1e\\+20"), (math.inf, "inf")):
        with pytest.raises(
            InvalidParameterError, match=rf"at most 5,000,000 points \(here {shown}\)"
        ):
            size_within("step", 1e-3, count, 5_000_000, "points")
    with pytest.raises(InvalidParameterError, match="here nan"):
        size_within("step", 1e-3, math.nan, 5_000_000, "points")


def test_capped_points_counts_before_reading() -> None:
    assert capped_points(np.zeros((4, 3)), "points", 4).shape == (4, 3)
    huge = np.broadcast_to(np.full(3, math.nan), (10**9, 3))  # a view: nothing allocated
    with pytest.raises(InvalidParameterError, match=r"invalid points=\(1000000000, 3\)"):
        capped_points(huge, "points", 4)
    with pytest.raises(InvalidParameterError, match="finite"):
        capped_points([[math.nan, 0, 0]], "points", 4)
