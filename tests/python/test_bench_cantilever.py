"""bench/study_cantilever.py without an mpm_geo run: the case it writes (the Sadeghirad beam of
docs/study/cantilever.md) and the run specifications it reads."""

import argparse
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "bench"))

import study_cantilever  # noqa: E402


@pytest.mark.parametrize("dx, nx, ny", [(0.25, 18, 22), (0.125, 36, 44), (0.0625, 72, 88)])
def test_case_geometry(dx, nx, ny):
    case = study_cantilever.cantilever_case(dx, "bspline3", "MUSL", "apic", 2)
    assert case["domain"]["nx"] == nx and case["domain"]["ny"] == ny
    assert case["domain"]["boundaries"]["xmin"] == "fixed"
    assert case["bodies"][0]["min"] == [0.0, 4.0] and case["bodies"][0]["max"] == [4.0, 5.0]
    assert case["solver"] == {"scheme": "MUSL", "shape_function": "bspline3",
                              "transfer": "apic"}
    assert case["time"]["tend"] == 3.0 and case["gravity"] == [0.0, -10.0]
    assert case["materials"][0]["type"] == "neo_hookean"
    assert "." not in case["name"]


def test_parse_run():
    assert study_cantilever.parse_run("0.125:bspline2:MUSL:flip:3") == (
        0.125, "bspline2", "MUSL", "flip", 3)
    with pytest.raises(argparse.ArgumentTypeError):
        study_cantilever.parse_run("0.125:bspline2:MUSL")
