"""tir_common.schema: one validator for meta.json, the parameter file and run headers."""

from __future__ import annotations

import math

import pytest

from tir_common.schema import Field, FieldError, Schema


@pytest.mark.parametrize(
    ("field", "expected"),
    [
        (Field("fps", "number", low=0, low_open=True), "a number > 0"),
        (Field("m", "number", low=0), "a number >= 0"),
        (Field("f", "number", low=0, high=1), "a number in [0, 1]"),
        (Field("x", "number"), "a finite number"),
        (Field("n", "integer", low=0), "an integer >= 0"),
        (Field("run", "integer"), "an integer"),
        (Field("kind", "choice", choices=("steady", "instationary")),
         "one of 'steady', 'instationary'"),
        (Field("ok", "bool"), "true or false"),
        (Field("law", "text"), "text"),
    ],
)
def test_expected_says_type_and_range(field, expected):
    assert field.expected() == expected


def test_numbers_from_text_and_json():
    area = Field("nominal_area_mm2", "number", low=0, low_open=True)
    assert area.check("12,5", from_text=True, decimal=",") == 12.5
    assert area.check("12.5", from_text=True, decimal=",") == 12.5
    assert area.check(3) == 3.0 and isinstance(area.check(3), float)
    for bad in ("12.5", True, None, math.nan, math.inf, -1.0, 0.0):
        with pytest.raises(FieldError, match=r"'nominal_area_mm2' must be a number > 0, got"):
            area.check(bad)
    n = Field("n_sipes", "integer", low=0)
    assert n.check(2.0) == 2 and isinstance(n.check(2.0), int)
    assert n.check("3", from_text=True) == 3
    with pytest.raises(FieldError, match=r"'n_sipes' must be an integer >= 0, got 2.5 \(float\)"):
        n.check(2.5)


def test_choice_lists_and_mappings():
    view = Field("view", "choice", choices=("tir", "side"))
    assert view.check(" TIR ") == "tir"
    with pytest.raises(FieldError, match=r"'view' must be one of 'tir', 'side', got 'top'"):
        view.check("top")
    lengths = Field("lengths_mm", "numbers")
    assert lengths.check((1, 2.5)) == [1.0, 2.5]
    with pytest.raises(FieldError, match=r"'lengths_mm\[1\]' must be a finite number, got nan"):
        lengths.check([1.0, math.nan])
    stderr = Field("stderr", "mapping")
    assert stderr.check({"a": 1, "b": math.inf, "c": None}) == {"a": 1.0, "b": None, "c": None}
    with pytest.raises(FieldError, match=r"'stderr.a' must be a number or null, got 'x'"):
        stderr.check({"a": "x"})


def test_schema_checks_a_record():
    schema = Schema(
        "geometry",
        (Field("length_mm", "number", required=True, low=0, low_open=True),
         Field("n_sipes", "integer", low=0)),
    )
    assert schema.check({"length_mm": 20, "n_sipes": None}) == {"length_mm": 20.0}
    with pytest.raises(FieldError, match=r"^'geometry.length_mm' is missing$"):
        schema.check({"n_sipes": 1}, prefix="geometry.")
    with pytest.raises(FieldError, match=r"'geometry.n_sipes' must be an integer >= 0, got -1"):
        schema.check({"length_mm": 20, "n_sipes": -1}, prefix="geometry.")
    with pytest.raises(FieldError, match=r"'geometry.colour' is not a known key of 'geometry'"):
        schema.check({"length_mm": 20, "colour": "red"}, prefix="geometry.")
    with pytest.raises(FieldError, match=r"'geometry' must be a JSON object, got list"):
        schema.check([1], prefix="geometry.")
    open_schema = Schema("metadata", schema.fields, closed=False)
    assert open_schema.check({"length_mm": 1, "colour": "red"}) == {
        "length_mm": 1.0,
        "colour": "red",
    }


def test_field_rejects_unknown_kinds():
    with pytest.raises(ValueError, match="kind must be one of"):
        Field("x", "colour")
