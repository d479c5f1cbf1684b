#!/usr/bin/env python3
"""Accuracy against cost on two problems run through mpm_geo (called by bench/run_study.sh).

    .venv/bin/python bench/study_cases.py column --exe build/mpm_geo --out docs/study/column.csv
    .venv/bin/python bench/study_cases.py bui --exe build/mpm_geo --out docs/study/bui.csv

``column``: the laterally confined elastic column under its own weight (REFERENCES.md section 2,
the CB-Geo set-up: H = 0.1 m, rho = 1800 kg/m3, E = 1 MPa, nu = 0), brought to rest by kinetic
damping, for every shape function and scheme over a ladder of cells over the height
(``--cells``). Errors at the end, against the exact static solution written in the reference
(initial) coordinates Y of the particles:

- ``error`` (the one plotted): the L2 norm of sigma_yy - (-rho g (H - Y)) over the particles,
  weighted by their volume, divided by rho g H (the largest exact stress);
- ``base_stress_rel``: the mean sigma_yy of the lowest row of particles against the exact value
  at their height (the figure of the published benchmark: 4.85 % at 10 mm cells with linear
  shape functions);
- ``settlement_rel``: the mean vertical displacement of the top row of particles against the
  exact one. With nu = 0 the column is in uniaxial strain and the Jaumann-rate elastic law of
  mpm_geo integrates to sigma = E ln(stretch), so the exact displacement is
  u(Y) = (E / rho g) (exp(-rho g (H - Y) / E) - exp(-rho g H / E)) - Y; it differs from the
  small-strain formula of REFERENCES.md by 0.1 % here (the strain is at most 0.18 %).

``bui``: the collapse of Bui et al. (2008) as in validation/bui2008/bui2008.json (its material,
floor, walls, transfer, separation, time and output taken from that file at run time), with
only the shape function, the scheme and the cell size (``--dx``) changed; analysed with the
functions of validation/bui2008/check.py. ``error`` is |toe - measured toe| / measured toe;
``surface_rms_m`` the RMS difference between the simulated and the measured free surface.

One CSV line per run (written as soon as the run ends). A run that fails (mpm_geo exits with an
error, a particle leaves the grid, the analysis fails) is a line with status ``failed`` and
the reason, never a crash of the study. Two times per run: ``wall_s``, the time loop's wall
time as mpm_geo reports it (without start-up and the reading of the case), and ``cpu_s``, the
CPU time of the mpm_geo process (start-up included), which other programs sharing the cores
do not inflate. Each column run shorter than 5 s (CPU) is repeated and the fastest of three
kept, the machine's noise only ever adding time. Run on one thread: OMP_NUM_THREADS=1 (the
default here when it is not set; run_study.sh sets it).
"""

import argparse
import csv
import json
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "postproc"))
sys.path.insert(0, str(REPO / "validation" / "bui2008"))

import numpy as np  # noqa: E402

from mpm_post import list_outputs, load_history, load_particles  # noqa: E402

SHAPES = ("linear", "cpgimp")
SCHEMES = ("USF", "USL", "MUSL")

# Self-weight column (REFERENCES.md section 2, CB-Geo benchmark parameters).
COLUMN_HEIGHT = 0.1       # H [m]
COLUMN_RHO = 1800.0       # [kg/m3]
COLUMN_E = 1.0e6          # [Pa]
COLUMN_NU = 0.0
GRAVITY = 9.81            # [m/s2]
COLUMN_WIDTH_CELLS = 2    # sliding walls: the solution does not depend on the width
COLUMN_CELLS = (4, 8, 16, 32, 64, 128)
# Simulated time in periods of the column's first mode, 4 H / c_p. Kinetic damping brings the
# column to rest within 5 of them at 64 and 128 cells (the errors of 5, 10, 20 and 40 periods
# agree to 1e-13); 10 leaves a margin. kinetic / strain energy at the end is in the CSV.
COLUMN_PERIODS = 10.0
COLUMN_CFL = 0.5
REPEAT_BELOW = 5.0        # [s] column runs shorter than this are repeated, the fastest kept
REPEATS = 3

BUI_DX = (0.01, 0.005, 0.0025)
RUN_TIMEOUT = 3600.0      # [s] a run that takes longer is recorded as failed

COLUMN_FIELDS = ["problem", "shape", "scheme", "cells", "dx_m", "particles", "steps", "wall_s",
                 "cpu_s", "error", "stress_l2_rel", "base_stress_rel", "settlement_rel",
                 "displacement_l2_rel", "kinetic_over_strain", "status", "note"]
BUI_FIELDS = ["problem", "shape", "scheme", "cells", "dx_m", "particles", "steps", "wall_s",
              "cpu_s", "error", "toe_m", "surface_rms_m", "height_at_wall_m", "volume_change",
              "kinetic_final_over_peak", "status", "note"]


# ---------------------------------------------------------------------------------------------
# running mpm_geo
# ---------------------------------------------------------------------------------------------

def _summary_number(text, label):
    """The number after ``label`` in mpm_geo's summary (None when absent)."""
    match = re.search(rf"^\s*{label}\s+([-+0-9.eE]+)", text, flags=re.MULTILINE)
    return float(match.group(1)) if match else None


def run_case(exe, case, workdir):
    """Run mpm_geo on ``case`` (a dict) in ``workdir``; returns (output dir, summary dict).

    The summary has ``wall_s`` (the time loop, from mpm_geo's summary; the process time when
    the summary has none), ``cpu_s`` (CPU time of the whole process, start-up included: the
    cost that other programs sharing the cores do not inflate), ``steps`` and ``particles``.
    Raises RuntimeError with mpm_geo's error message when it fails or times out.
    """
    workdir = Path(workdir)
    case_path = workdir / f"{case['name']}.json"
    case_path.write_text(json.dumps(case, indent=1), encoding="utf-8")
    output = workdir / case["name"]
    command = [str(exe), str(case_path), "--output", str(output), "--overwrite"]
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
    start = time.perf_counter()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        result = subprocess.run(command, capture_output=True, text=True, check=False,
                                timeout=RUN_TIMEOUT, env=env)
    except subprocess.TimeoutExpired:
        raise RuntimeError(f"no result after {RUN_TIMEOUT:g} s") from None
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if result.returncode != 0:
        lines = [line.strip() for line in (result.stderr + "\n" + result.stdout).splitlines()
                 if line.strip()]
        errors = [line for line in lines if "error" in line.lower()]
        reason = (errors[0] if errors else " / ".join(lines[-2:])) if lines else "no message"
        reason = reason.removeprefix("mpm_geo: error: ")
        raise RuntimeError(f"mpm_geo exit code {result.returncode}: {reason}")
    wall = _summary_number(result.stdout, "wall time")
    steps = _summary_number(result.stdout, "steps")
    particles = _summary_number(result.stdout, "particles")
    return output, {"wall_s": wall if wall is not None else elapsed, "cpu_s": cpu,
                    "steps": int(steps) if steps is not None else None,
                    "particles": int(particles) if particles is not None else None}


class CsvLog:
    """A CSV file written line by line, so that an interrupted study keeps its finished runs."""

    def __init__(self, path, fields):
        self.fields = fields
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        self.handle = open(path, "w", newline="", encoding="utf-8")
        self.writer = csv.DictWriter(self.handle, fieldnames=fields, extrasaction="ignore")
        self.writer.writeheader()
        self.handle.flush()

    def write(self, row):
        clean = {}
        for key in self.fields:
            value = row.get(key)
            if value is None or (isinstance(value, float) and not math.isfinite(value)):
                clean[key] = ""
            elif isinstance(value, float):
                clean[key] = f"{value:.6g}"
            else:
                clean[key] = str(value).replace("\n", " ")
        self.writer.writerow(clean)
        self.handle.flush()

    def close(self):
        self.handle.close()


def _progress(row):
    if row["status"] == "ok":
        shown = f"error {row['error']:.3g}, CPU {row['cpu_s']:.3g} s, wall {row['wall_s']:.3g} s"
    else:
        shown = f"FAILED: {row['note']}"
    print(f"study: {row['problem']} {row['shape']:>6} {row['scheme']:<4} {row['cells']:>4} "
          f"cells: {shown}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# self-weight column
# ---------------------------------------------------------------------------------------------

def column_wave_speed():
    """P-wave speed of the column [m/s]: sqrt((K + 4G/3) / rho)."""
    modulus = COLUMN_E * (1 - COLUMN_NU) / ((1 + COLUMN_NU) * (1 - 2 * COLUMN_NU))
    return math.sqrt(modulus / COLUMN_RHO)


def column_case(cells, shape, scheme):
    """The case of the column with ``cells`` cells over its height."""
    dx = COLUMN_HEIGHT / cells
    tend = COLUMN_PERIODS * 4.0 * COLUMN_HEIGHT / column_wave_speed()
    width = COLUMN_WIDTH_CELLS * dx
    return {
        "name": f"column_{shape}_{scheme}_{cells}".lower(),
        "domain": {"nx": COLUMN_WIDTH_CELLS, "ny": cells + 2, "dx": dx,
                   "boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}},
        "particles": {"ppc": 2},
        "materials": [{"name": "soil", "type": "linear_elastic", "E": COLUMN_E,
                       "nu": COLUMN_NU, "rho": COLUMN_RHO}],
        "bodies": [{"material": "soil", "min": [0.0, 0.0], "max": [width, COLUMN_HEIGHT]}],
        "gravity": [0.0, -GRAVITY],
        "solver": {"scheme": scheme, "shape_function": shape},
        "time": {"tend": tend, "cfl": COLUMN_CFL},
        "damping": {"type": "kinetic"},
        "output": {"interval": 0, "history_interval": tend / 50,
                   "fields": ["position", "displacement", "stress", "volume", "mass"]},
        "progress": {"interval": 3600},
    }


def column_exact_stress(y_ref):
    """Exact sigma_yy [Pa] at reference height ``y_ref`` [m] (tension positive)."""
    return -COLUMN_RHO * GRAVITY * (COLUMN_HEIGHT - np.asarray(y_ref, dtype=float))


def column_exact_displacement(y_ref):
    """Exact vertical displacement [m] at reference height ``y_ref`` (nu = 0, see the top)."""
    a = COLUMN_RHO * GRAVITY / COLUMN_E
    y_ref = np.asarray(y_ref, dtype=float)
    return (np.exp(-a * (COLUMN_HEIGHT - y_ref)) - math.exp(-a * COLUMN_HEIGHT)) / a - y_ref


def column_errors(data, dx):
    """Errors of the last output ``data`` (a dict of load_particles) of a column run."""
    position = np.asarray(data["position"], dtype=float)
    displacement = np.asarray(data["displacement"], dtype=float)
    y_ref = position[:, 1] - displacement[:, 1]
    syy = np.asarray(data["stress"], dtype=float)[:, 1]
    volume = np.asarray(data["volume"], dtype=float)
    mass = np.asarray(data["mass"], dtype=float)
    if not (np.all(np.isfinite(syy)) and np.all(np.isfinite(position))):
        raise ValueError("non-finite stress or position at the end")
    exact = column_exact_stress(y_ref)
    scale = COLUMN_RHO * GRAVITY * COLUMN_HEIGHT
    l2 = math.sqrt(float(np.sum(volume * (syy - exact) ** 2) / np.sum(volume))) / scale
    tol = 1.0e-6 * dx
    base = y_ref <= y_ref.min() + tol
    base_syy = float(np.sum(mass[base] * syy[base]) / np.sum(mass[base]))
    base_exact = float(column_exact_stress(y_ref[base].mean()))
    top = y_ref >= y_ref.max() - tol
    settle = float(np.mean(displacement[top, 1]))
    settle_exact = float(column_exact_displacement(y_ref[top].mean()))
    u_exact = column_exact_displacement(y_ref)
    u_l2 = math.sqrt(float(np.sum(volume * (displacement[:, 1] - u_exact) ** 2)
                           / np.sum(volume))) / float(np.max(np.abs(u_exact)))
    return {"error": l2, "stress_l2_rel": l2,
            "base_stress_rel": abs(base_syy / base_exact - 1.0),
            "settlement_rel": abs(settle / settle_exact - 1.0),
            "displacement_l2_rel": u_l2}


def run_column(exe, cells, shape, scheme, workdir):
    """One row of the column study (status ``failed`` with the reason when it fails)."""
    case = column_case(cells, shape, scheme)
    row = {"problem": "column", "shape": shape, "scheme": scheme, "cells": cells,
           "dx_m": case["domain"]["dx"], "status": "failed", "note": ""}
    try:
        best = None
        for _ in range(REPEATS):
            output, summary = run_case(exe, case, workdir)
            if best is None or summary["cpu_s"] < best["cpu_s"]:
                best = summary
            if summary["cpu_s"] >= REPEAT_BELOW:
                break
        outputs = list_outputs(output)
        if not outputs:
            raise RuntimeError("no output written")
        data = load_particles(outputs[-1][1])
        row.update(column_errors(data, case["domain"]["dx"]))
        history = load_history(output)
        strain = float(history["elastic_energy" if "elastic_energy" in history
                               else "strain_energy"][-1])
        row["kinetic_over_strain"] = (float(history["kinetic_energy"][-1]) / strain
                                      if strain > 0 else math.nan)
        row.update(best)
        row["status"] = "ok"
    except (RuntimeError, ValueError, KeyError, OSError) as exc:
        row["note"] = str(exc)
    return row


# ---------------------------------------------------------------------------------------------
# Bui et al. (2008) collapse
# ---------------------------------------------------------------------------------------------

def bui_case(check, dx, shape, scheme):
    """The validation case with cells of ``dx`` [m] and the given shape function and scheme."""
    case = check.coarse_case(check.load_case(check.CASE), dx)
    case["solver"] = dict(case.get("solver", {}), shape_function=shape, scheme=scheme)
    case["name"] = f"bui_{shape}_{scheme}_{round(dx * 1e4)}".lower()
    case["progress"] = {"interval": 3600}
    return case


def run_bui(exe, dx, shape, scheme, workdir, check, exp):
    """One row of the Bui study (status ``failed`` with the reason when it fails)."""
    cells = round(check.COLUMN_HEIGHT / dx)
    row = {"problem": "bui", "shape": shape, "scheme": scheme, "cells": cells, "dx_m": dx,
           "status": "failed", "note": ""}
    try:
        case = bui_case(check, dx, shape, scheme)
        output, summary = run_case(exe, case, workdir)
        row.update(summary)
        metrics, _ = check.analyse(output, case, exp)
        toe = metrics["toe_m"]
        if not math.isfinite(toe):
            raise ValueError("no toe found in the final deposit")
        row.update({"error": abs(toe - exp["toe_m"]) / exp["toe_m"], "toe_m": toe,
                    "surface_rms_m": metrics["surface_rms_m"],
                    "height_at_wall_m": metrics["height_at_wall_m"],
                    "volume_change": metrics["volume_relative_change"],
                    "kinetic_final_over_peak": metrics["kinetic_final_over_peak"]})
        if metrics["deposit_reaches_end_wall"]:
            row["note"] = "the deposit reaches the end wall"
        row["status"] = "ok"
    except (RuntimeError, ValueError, KeyError, OSError, IndexError) as exc:
        row["note"] = str(exc)
    return row


# ---------------------------------------------------------------------------------------------
# main
# ---------------------------------------------------------------------------------------------

def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("problem", choices=("column", "bui"))
    parser.add_argument("--exe", default=str(REPO / "build" / "mpm_geo"),
                        help="mpm_geo executable (default: build/mpm_geo)")
    parser.add_argument("--out", required=True, help="CSV file to write")
    parser.add_argument("--cells", type=int, nargs="+", default=list(COLUMN_CELLS),
                        help="column: cells over the height (default: %(default)s)")
    parser.add_argument("--dx", type=float, nargs="+", default=list(BUI_DX),
                        help="bui: cell sizes [m] (default: %(default)s)")
    parser.add_argument("--shapes", nargs="+", default=list(SHAPES), choices=SHAPES)
    parser.add_argument("--schemes", nargs="+", default=list(SCHEMES), choices=SCHEMES)
    parser.add_argument("--keep", default=None,
                        help="folder to keep the run outputs in (default: a temporary folder)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if not os.access(args.exe, os.X_OK):
        print(f"study_cases.py: executable not found: {args.exe} (make build)", file=sys.stderr)
        return 2
    if args.problem == "column":
        log = CsvLog(args.out, COLUMN_FIELDS)
        ladder = sorted(args.cells)
    else:
        import check  # validation/bui2008/check.py
        log = CsvLog(args.out, BUI_FIELDS)
        ladder = sorted(args.dx, reverse=True)
        exp = check.experiment()
    with tempfile.TemporaryDirectory(prefix="mpm_study_") as tmp:
        workdir = Path(args.keep) if args.keep else Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        for shape in args.shapes:
            for scheme in args.schemes:
                for step in ladder:
                    if args.problem == "column":
                        row = run_column(args.exe, step, shape, scheme, workdir)
                    else:
                        row = run_bui(args.exe, step, shape, scheme, workdir, check, exp)
                    log.write(row)
                    _progress(row)
                    if not args.keep:  # the Bui outputs are tens of MB per run
                        for path in Path(tmp).iterdir():
                            if path.is_dir():
                                shutil.rmtree(path, ignore_errors=True)
    log.close()
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
