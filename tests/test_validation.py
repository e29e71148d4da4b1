"""The shared argument checks (orthoglide_pin._validation): what each accepts and refuses."""

from __future__ import annotations

import math
from collections import OrderedDict
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from orthoglide_pin._validation import (
    choice,
    finite_number,
    flag,
    integer,
    mapping,
    mappings,
    name_list,
    optional_callable,
    path_argument,
    positive_limit,
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
