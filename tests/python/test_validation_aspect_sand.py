"""validation/aspect_ratio/check.py --sand without an mpm_geo run: the published runouts it
compares with, and the sand case it derives from the Bui case."""

import importlib.util
import math
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
# loaded under its own name: every validation case has a check.py
_SPEC = importlib.util.spec_from_file_location(
    "aspect_ratio_check", REPO / "validation" / "aspect_ratio" / "check.py")
check = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(check)


def test_lube_runouts():
    assert check.lube_runout(1.0) == (1.2, 1.2)                      # 1.2 a
    low, high = check.lube_runout(3.0)                               # 1.9 a^(2/3)
    assert low == high and math.isclose(high, 1.9 * 3.0 ** (2.0 / 3.0))
    low, high = check.lube_runout(2.0)                               # the transition
    assert math.isclose(low, 2.4) and math.isclose(high, 1.9 * 2.0 ** (2.0 / 3.0))


def test_the_sand_case():
    bui = check.load_json(check.BUI_CASE)
    case = check.sand_case(bui, 2.0, 32)
    assert case["name"] == "aspect_ratio_a2_sand32"
    assert case["materials"][0]["phi"] == 30.0
    assert case["materials"][0]["c"] == bui["materials"][0]["c"]
    assert math.isclose(case["domain"]["boundaries"]["ymin"]["mu"], math.tan(math.radians(30)),
                        abs_tol=1e-4)
    assert math.isclose(case["domain"]["dx"], 0.2 / 32)
    # the sweep case of the Bui material is untouched
    assert check.sweep_case(bui, 2.0)["materials"][0]["phi"] == bui["materials"][0]["phi"]
