"""The scene reader's refusal of a segment option its law does not take
(camgen.motions.motion_law.read_program): the option's scene key, the value, "no <option> for a
<law> segment" and the laws that take it (the segment schema's docs: SEGMENT_KEYS), for every
option, before the segment is built; a segment without options is read as before."""
from __future__ import annotations

import math

import pytest

from camgen.errors import ParameterError
from camgen.motions.motion_law import read_program

D = math.radians
#: Each option, a value, and the laws its key's doc names (camgen/motions/motion_law.py SEGMENT_KEYS).
OPTIONS = [("blend", 0.2, "constant_velocity"), ("start", (0.0, 0.0, 0.0), "polynomial or bspline"),
           ("end", (1.0, 0.0, 0.0), "polynomial or bspline"), ("scca", (0.25, 0.5, 0.25), "scca"),
           ("accel_fraction", 0.4, "asymmetric_modified_sine or asymmetric_modified_trapezoid"),
           ("points", ((0.5, 1.0),), "bspline"), ("degree", 5, "bspline"), ("interior", ((0.5, 1.0),), "polynomial")]


def _segments(option: dict) -> tuple[dict, ...]:
    return ({"law": "cycloidal", "span": D(120.0), "lift": 10.0, **option}, {"law": "dwell", "span": D(60.0)},
            {"law": "cycloidal", "span": D(120.0), "lift": -10.0}, {"law": "dwell", "span": D(60.0)})


@pytest.mark.parametrize("name, value, owners", OPTIONS)
def test_an_option_of_another_law_is_refused_naming_it_and_its_laws(name, value, owners):
    with pytest.raises(ParameterError) as info:
        read_program("cams.c", _segments({name: value}), "translating")
    assert info.value.name == f"cams.c.segments[0].{name}"
    assert info.value.value == value
    assert info.value.valid == f"no {name} for a cycloidal segment"
    assert info.value.why == f"only for {owners}"


def test_a_segment_without_options_is_read():
    program = read_program("cams.c", _segments({}), "translating")
    assert [seg.lift for seg in program.segments] == [10.0, 0.0, -10.0, 0.0]
    assert program.stroke == 10.0
