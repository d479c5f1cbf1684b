"""Helpers shared by the validation scripts (validation/<case>/check.py).

- ``relative``: a path relative to the repository, for the reports;
- ``target``: one compared figure of a report (the dicts of its ``targets`` list), and
  ``verdict``, its state as printed: pass, FAIL or outside (reported);
- ``write_json``: a report as JSON, NaN and infinities written as null, numpy scalars as numbers;
- ``load_json``: a case file or a report;
- ``agg_figure``: a matplotlib figure on the Agg canvas (no display needed);
- ``exe_version``: what ``mpm_geo --version`` prints;
- ``shown`` and ``print_table``: the table of targets a script prints;
- ``common_arguments`` and ``exe_missing``: the command-line options every script has (--exe,
  --output, --results, --no-run, --quiet) and the check of the executable.
"""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
DEFAULT_EXE = REPO / "build" / "mpm_geo"
EXE_HELP = "mpm_geo executable (default: build/mpm_geo)"
NO_RUN_HELP = "analyse the existing outputs instead of running"
QUIET_HELP = "no progress lines from mpm_geo"
PARENT_OUTPUT_HELP = ("parent folder of the runs' output folders (default: outputs/, each run "
                      "overwriting outputs/<case name>); folders under a parent given here must "
                      "not exist")


def relative(path, repo=REPO):
    """``path`` relative to the repository when it lies inside it."""
    try:
        return str(Path(path).resolve().relative_to(repo))
    except ValueError:
        return str(path)


def target(name, value, reference, band, passed, gating, why, unit=""):
    """One compared figure of a report.

    ``reference`` is the expected value (None when there is none), ``band`` the text of the
    allowed range, ``gating`` whether missing it fails the check, ``why`` the reason for the
    band and ``unit`` how to show the value: m, mm (value in m), deg, % (value a fraction), rel,
    or "" (a script may change this default, bui2008 uses m).
    """
    return {"name": name, "value": value, "reference": reference, "band": band,
            "passed": bool(passed), "gating": gating, "why": why, "unit": unit}


def verdict(result):
    """State of a target as printed: pass, FAIL (gating) or outside (reported)."""
    if result["passed"]:
        return "pass"
    return "FAIL" if result["gating"] else "outside (reported)"


def _clean(value, str_keys):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {(str(k) if str_keys else k): _clean(v, str_keys) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v, str_keys) for v in value]
    if isinstance(value, np.generic):
        return _clean(value.item(), str_keys)
    return value


def write_json(path, data, str_keys=False):
    """Write ``data`` to ``path`` as indented JSON, creating the folder.

    NaN and infinities become null (JSON has no such numbers), tuples lists and numpy scalars
    Python numbers. ``str_keys`` turns every dict key into ``str(key)`` first (aspect_ratio);
    otherwise the keys go to ``json`` as they are.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_clean(data, str_keys), indent=2) + "\n", encoding="utf-8")


def load_json(path):
    """The JSON document of a file (a case file, a report)."""
    with open(path, encoding="utf-8") as handle:
        return json.load(handle)


def agg_figure(width, height):
    """A matplotlib figure of ``width`` x ``height`` inches, constrained layout, Agg canvas."""
    from .plots import _figure
    return _figure(width, height)


def exe_version(exe):
    """What ``exe --version`` prints (None when it prints nothing or does not run)."""
    try:
        result = subprocess.run([str(exe), "--version"], capture_output=True, text=True,
                                check=False, timeout=30)
        return result.stdout.strip() or None
    except OSError:
        return None


def shown(value, unit):
    """A value as printed in the table of targets, after its unit.

    m: 4 decimals, mm: the value in m shown in mm with 1 decimal, %: a fraction as a signed
    percentage, "": 3 significant digits, any other unit (deg): 1 decimal and the unit.
    n/a for None, NaN and infinities.
    """
    if value is None or not math.isfinite(value):
        return "n/a"
    if unit == "mm":
        return f"{value * 1e3:.1f} mm"
    if unit == "m":
        return f"{value:.4f} m"
    if unit == "%":
        return f"{value:+.1%}"
    if unit == "":
        return f"{value:.3g}"
    return f"{value:.1f} {unit}"


def print_table(results, widths, reference="reference"):
    """Print the targets as a table: figure, model, reference, band and verdict.

    ``widths`` are those of the figure, model, reference and band columns, ``reference`` the
    heading of the reference column.
    """
    name, model, ref, band = widths
    print(f"{'figure':<{name}} {'model':>{model}} {reference:>{ref}}  {'band':<{band}} result")
    for t in results:
        value = "-" if t["reference"] is None else shown(t["reference"], t["unit"])
        print(f"{t['name']:<{name}} {shown(t['value'], t['unit']):>{model}} {value:>{ref}}  "
              f"{t['band']:<{band}} {verdict(t)}")


def common_arguments(parser, results, output_help=None, results_help=None, exe_help=EXE_HELP,
                     no_run_help=NO_RUN_HELP, quiet_help=QUIET_HELP):
    """Add --exe, --output, --results, --no-run and --quiet to an argparse ``parser``.

    ``results`` is the default results folder; the help of --results is ``results_help``, by
    default "folder for metrics and plots (default: <results relative to the repository>)".
    --output (default None) is added only when ``output_help`` is given, since what it names
    (a run folder or the parent of several) belongs to the script. Returns the parser.
    """
    parser.add_argument("--exe", default=str(DEFAULT_EXE), help=exe_help)
    if output_help is not None:
        parser.add_argument("--output", default=None, help=output_help)
    if results_help is None:
        results_help = f"folder for metrics and plots (default: {relative(results)})"
    parser.add_argument("--results", default=str(results), help=results_help)
    parser.add_argument("--no-run", action="store_true", help=no_run_help)
    parser.add_argument("--quiet", action="store_true", help=quiet_help)
    return parser


def exe_missing(exe):
    """True, after saying so on stderr, when ``exe`` is not an executable file."""
    if os.access(exe, os.X_OK):
        return False
    print(f"check.py: executable not found: {exe} (make build)", file=sys.stderr)
    return True
