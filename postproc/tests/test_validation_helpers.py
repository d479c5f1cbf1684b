"""mpm_post.validation: the helpers shared by the validation scripts (validation/*/check.py)."""

import argparse
import json
import math

import numpy as np
import pytest

from mpm_post.validation import (REPO, agg_figure, common_arguments, exe_missing, exe_version,
                                 load_json, print_table, relative, shown, target, verdict,
                                 write_json)


def old_write_json(path, data):
    """The copy the scripts had before (sliding_block, bui2008, vibrating_bar, ...)."""
    path.parent.mkdir(parents=True, exist_ok=True)

    def clean(value):
        if isinstance(value, float) and not math.isfinite(value):
            return None
        if isinstance(value, dict):
            return {k: clean(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [clean(v) for v in value]
        if isinstance(value, np.generic):
            return clean(value.item())
        return value

    path.write_text(json.dumps(clean(data), indent=2) + "\n", encoding="utf-8")


SAMPLE = {
    "nan": math.nan, "inf": math.inf, "minus_inf": -math.inf, "float": 0.1, "int": 3,
    "none": None, "bool": True, "text": "a b",
    "np_float": np.float64(2.5), "np_nan": np.float64("nan"), "np_float32": np.float32(0.5),
    "np_float32_inf": np.float32("inf"), "np_int": np.int64(7), "np_bool": np.bool_(False),
    "tuple": (1.0, math.nan, np.int32(2)), "nested": {"list": [math.inf, {"x": np.nan}]},
    "empty": [],
}


# --- write_json ---------------------------------------------------------------------------

def test_write_json_same_text_as_the_old_copies(tmp_path):
    write_json(tmp_path / "new" / "metrics.json", SAMPLE)
    old_write_json(tmp_path / "old" / "metrics.json", SAMPLE)
    new = (tmp_path / "new" / "metrics.json").read_text(encoding="utf-8")
    assert new == (tmp_path / "old" / "metrics.json").read_text(encoding="utf-8")
    assert new.endswith("}\n")


def test_write_json_same_text_as_the_column3d_and_mms_copies(tmp_path):
    """Those copies cleaned lists only and left numpy scalars to json: same text on what they
    could write (np.float64 is a float)."""
    def clean(value):
        if isinstance(value, float) and not math.isfinite(value):
            return None
        if isinstance(value, dict):
            return {k: clean(v) for k, v in value.items()}
        if isinstance(value, list):
            return [clean(v) for v in value]
        return value

    data = {k: v for k, v in SAMPLE.items()
            if k not in ("np_float32", "np_float32_inf", "np_int", "np_bool", "tuple")}
    write_json(tmp_path / "metrics.json", data)
    assert (tmp_path / "metrics.json").read_text(encoding="utf-8") == \
        json.dumps(clean(data), indent=2) + "\n"


def test_write_json_round_trip(tmp_path):
    path = tmp_path / "a" / "b" / "metrics.json"       # the folders are created
    write_json(path, SAMPLE)
    back = load_json(path)
    assert back["nan"] is None and back["inf"] is None and back["minus_inf"] is None
    assert back["np_nan"] is None and back["np_float32_inf"] is None
    assert back["float"] == 0.1 and back["int"] == 3 and back["bool"] is True
    assert back["np_float"] == 2.5 and back["np_float32"] == 0.5
    assert back["np_int"] == 7 and back["np_bool"] is False
    assert back["tuple"] == [1.0, None, 2]
    assert back["nested"] == {"list": [None, {"x": None}]}
    assert back["none"] is None and back["empty"] == [] and back["text"] == "a b"
    # strict JSON: no NaN or Infinity literals
    json.loads(path.read_text(encoding="utf-8"), parse_constant=pytest.fail)


def test_write_json_keys(tmp_path):
    data = {0.5: 1, 2: {True: math.nan}, "a": 3}
    write_json(tmp_path / "plain.json", data)
    assert load_json(tmp_path / "plain.json") == {"0.5": 1, "2": {"true": None}, "a": 3}
    # str_keys (aspect_ratio): str() of every key, also where json would refuse the key
    write_json(tmp_path / "str.json", dict(data, **{"b": {(1, 2): 4}}), str_keys=True)
    assert load_json(tmp_path / "str.json") == {"0.5": 1, "2": {"True": None}, "a": 3,
                                                "b": {"(1, 2)": 4}}


# --- target, verdict, the printed table -----------------------------------------------------

def test_target_fields():
    t = target("toe", 0.41, 0.4, "within 5 %", np.bool_(True), True, "the issue")
    assert list(t) == ["name", "value", "reference", "band", "passed", "gating", "why", "unit"]
    assert t == {"name": "toe", "value": 0.41, "reference": 0.4, "band": "within 5 %",
                 "passed": True, "gating": True, "why": "the issue", "unit": ""}
    assert type(t["passed"]) is bool
    assert target("a", 1.0, None, "b", 0, False, "w", unit="mm")["unit"] == "mm"
    assert target("a", 1.0, None, "b", 0, False, "w")["passed"] is False


def test_verdict():
    assert verdict(target("a", 1, None, "", True, True, "")) == "pass"
    assert verdict(target("a", 1, None, "", True, False, "")) == "pass"
    assert verdict(target("a", 1, None, "", False, True, "")) == "FAIL"
    assert verdict(target("a", 1, None, "", False, False, "")) == "outside (reported)"


def test_shown():
    assert shown(0.412345, "m") == "0.4123 m"
    assert shown(0.00512, "mm") == "5.1 mm"
    assert shown(0.123, "%") == "+12.3%"
    assert shown(12.345, "deg") == "12.3 deg"
    assert shown(0.012345, "") == "0.0123"
    for missing in (None, math.nan, math.inf):
        assert shown(missing, "m") == "n/a"


def test_print_table(capsys):
    results = [target("toe", 0.41, 0.4, "within 5 %", True, True, "", unit="m"),
               target("RMS", 0.006, None, "<= 5 mm", False, True, "", unit="mm"),
               target("angle", 50.0, 45.0, "within 5 deg", False, False, "", unit="deg")]
    print_table(results, (22, 10, 11, 16), reference="experiment")
    lines = capsys.readouterr().out.splitlines()
    assert lines == [
        f"{'figure':<22} {'model':>10} {'experiment':>11}  {'band':<16} result",
        f"{'toe':<22} {'0.4100 m':>10} {'0.4000 m':>11}  {'within 5 %':<16} pass",
        f"{'RMS':<22} {'6.0 mm':>10} {'-':>11}  {'<= 5 mm':<16} FAIL",
        f"{'angle':<22} {'50.0 deg':>10} {'45.0 deg':>11}  {'within 5 deg':<16} "
        "outside (reported)",
    ]


# --- command line -----------------------------------------------------------------------------

def test_common_arguments_defaults():
    results = REPO / "validation" / "some_case" / "results"
    parser = common_arguments(argparse.ArgumentParser(), results, output_help="run folder")
    args = parser.parse_args([])
    assert args.exe == str(REPO / "build" / "mpm_geo")
    assert args.output is None
    assert args.results == str(results)
    assert args.no_run is False and args.quiet is False
    args = parser.parse_args(["--exe", "x", "--output", "o", "--results", "r", "--no-run",
                              "--quiet"])
    assert (args.exe, args.output, args.results, args.no_run, args.quiet) == \
        ("x", "o", "r", True, True)
    text = parser.format_help()
    assert "validation/some_case/results" in text and "run folder" in text


def test_common_arguments_without_output_and_own_help():
    parser = common_arguments(argparse.ArgumentParser(), "res", results_help="folder X",
                              exe_help="exe Y", no_run_help="again Z", quiet_help="quiet W")
    parser.add_argument("--study-exe", default=None)
    args = parser.parse_args([])
    assert not hasattr(args, "output") and args.study_exe is None and args.results == "res"
    with pytest.raises(SystemExit):
        parser.parse_args(["--output", "o"])
    text = " ".join(parser.format_help().split())
    for words in ("folder X", "exe Y", "again Z", "quiet W"):
        assert words in text


def test_exe_missing(tmp_path, capsys):
    assert exe_missing(tmp_path / "mpm_geo")
    assert "executable not found" in capsys.readouterr().err
    exe = tmp_path / "fake"
    exe.write_text("#!/bin/sh\necho 'mpm_geo 9.9'\n", encoding="utf-8")
    exe.chmod(0o755)
    assert not exe_missing(exe)
    assert exe_version(exe) == "mpm_geo 9.9"
    assert exe_version(tmp_path / "mpm_geo") is None


# --- paths and figures --------------------------------------------------------------------

def test_relative():
    assert relative(REPO / "validation" / "x.json") == "validation/x.json"
    assert relative("/somewhere/else.json") == "/somewhere/else.json"


def test_agg_figure(tmp_path):
    figure = agg_figure(4.0, 3.0)
    assert tuple(figure.get_size_inches()) == (4.0, 3.0)
    figure.add_subplot().plot([0, 1], [1, 0])
    figure.savefig(tmp_path / "f.png", dpi=50)
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
