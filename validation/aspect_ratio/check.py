#!/usr/bin/env python3
"""Validation: runout and final height of 2D granular column collapses against the aspect ratio.

A sweep of plane-strain columns, L0 wide and H0 = a L0 high against a wall at x = 0, released at
t = 0 and run until at rest, for a = 0.5, 1, 1.5, 2, 3, compared with the published trends of
quasi-2D channel experiments (docs: /work/shared/REFERENCES.md section 5; Lube et al. 2005,
Lajeunesse et al. 2005): (Lf - L0)/L0 ~ lambda a at small a (lambda about 1.2-1.35) and
1.9 a^(2/3) above a transition near a = 2-3; Hf/L0 = a while the top of the column survives.

The material (materials[0]), the wall and floor conditions (domain.boundaries), the particles per
cell (particles), the gravity, the whole solver object and the time-step rule (time without tend)
are copied from validation/bui2008/bui2008.json when this script runs, so that the sweep follows
that case when it changes. Only the geometry, the cell size, the end time and the output are set
here (SWEEP below).

    .venv/bin/python validation/aspect_ratio/check.py            run the sweep and compare
    .venv/bin/python validation/aspect_ratio/check.py --no-run   analyse the existing outputs
    .venv/bin/python validation/aspect_ratio/check.py --sand     the sand sweep (reported)

--sand runs the columns of issue 19's goal, a = 1, 2, 3, in a material like the sands of the
published sweeps (the Bui case with phi = 30 deg and a floor friction mu = tan(phi): a rough
floor), at 16 and 32 cells over L0 (12.5 and 6.25 mm), and compares (Lf - L0)/L0 with the
trend of Lube et al. (2005) within 30 % at both resolutions; reported (results/
metrics_sand.json, results/aspect_ratio_sand.png), exit 1 when a band is missed.

Outputs: outputs/aspect_ratio_a<a>/ (one run per a, with the generated case as case.json);
results/metrics.json, results/aspect_ratio.png (runout and final height against a) and
results/aspect_ratio_profiles.png (the final deposits).
Exit codes: 0 every gating target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import copy
import json
import math
import os
import resource
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post import list_outputs, load_history, load_particles  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.profiles import (  # noqa: E402
    bin_edges, free_surface, height_at_wall, load_reference_profile, max_height,
    particle_half_size, slip_angle, toe_position)
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, exe_version, load_json, print_table, relative,
    target, write_json)

BUI_DIR = REPO / "validation" / "bui2008"
BUI_CASE = BUI_DIR / "bui2008.json"
BUI_SURFACE = BUI_DIR / "data" / "Data_Buietal_2008_experimental_surface.txt"
BUI_FAILURE = BUI_DIR / "data" / "Data_Buietal_2008_experimental_failure_surface.txt"
BUI_WIDTH = 0.2          # L0 of the Bui et al. (2008) column [m]
RESULTS = HERE / "results"
CASE_FILE = "case.json"  # the generated case, written into each run's output folder

# --- the sweep ------------------------------------------------------------------------------
ASPECT_RATIOS = (0.5, 1.0, 1.5, 2.0, 3.0)
# L0 is the width of the Bui column, so that the a = 0.5 run is the Bui experiment's geometry.
COLUMN_WIDTH = BUI_WIDTH
# 16 cells over L0 (12.5 mm; 8 cells over the a = 0.5 column's height): the cost of a run grows
# as (L0/dx)^3 (particles times steps, the step being set by the elastic wave speed), and 16 keeps
# the five runs near 3 minutes on one thread; 20 cells (10 mm) take about twice as long.
CELLS_PER_WIDTH = 16
# End time: the deposits of 10 and 12.5 mm trial runs stopped (every particle within half a cell
# of its final place) at 5-6 sqrt(H0/g) for every a (a = 3: 1.45 s); 7 sqrt(H0/g) leaves a
# margin, and the rest window (REST_WINDOW) is added so that it lies after the stop.
FLOW_TIMES = 7.0
REST_WINDOW = 0.1        # the largest displacement over the last REST_WINDOW [s] shows rest
OUTPUT_INTERVAL = 0.05   # [s]
# Domain length: L0 (1 + DOMAIN_MARGIN R_env(a)) with R_env the upper envelope of the published
# runouts (max(1.35 a, 1.9 a^(2/3))). Margin 4: the Bui experiment, with this very material, ran
# out twice the sand trend at a = 0.5 (1.21 against 1.2 a = 0.6), MPM with Mohr-Coulomb runs out
# about 40 % further again at large a (Mast et al. 2014): 2 x 1.4 = 2.8, and the front sheds
# loose particles beyond the contiguous deposit.
DOMAIN_MARGIN = 4.0
# Domain height: 20 % above the column, as the Bui case (0.12 m over 0.1 m). The top face is
# closed (sliding) although the Bui case leaves it free: no deposit reaches it, but a particle
# thrown up by the volume blow-up described under INFLATION_LIMIT would stop the run
# (exit code 3, "left the grid") before the other particles are at rest.
HEIGHT_MARGIN = 1.2
# A particle whose area grew above INFLATION_LIMIT times its initial area is numerically broken:
# in trial runs (a = 2 and 3, 10 and 12.5 mm cells, before the fixes of the APIC lone particle
# and the small-mass nodes) a few particles of the thin front lying on the frictional floor grew
# from about 2 to 5, 30, then 1e7-1e20 times their area within 0.1-0.2 s and were thrown up.
# Healthy front particles (tearing of the thin sheet, kept as an opening by `separation`) grow
# at most 2.1 times for a <= 2 and 3.9-4.1 times at a = 3, where they stop (two runs of the same
# case that differ in round-off: 3.87 and 4.1). The limit, twice the largest healthy growth,
# lies between the two populations. Broken particles are left out of every measure below,
# counted, and fail a gating target; the largest growth of each run is reported.
INFLATION_LIMIT = 8.0

# --- the published trends (REFERENCES.md section 5) -----------------------------------------
# REFERENCES.md gives the small-a coefficient (1.2-1.35), the a^(2/3) growth above a
# transition near a = 2-3 and Hf/L0 ~ a at small a. The coefficient 1.9 of the a^(2/3) branch,
# the transitions 1.8 / 2.8 and the Hf ~ a^(2/5) branch are values of Lube et al. (2005) as
# quoted from secondary sources, not checked against the paper here: every target that uses
# them is reported, not gating.
LAMBDA_PUBLISHED = (1.2, 1.35)   # (Lf - L0)/L0 = lambda a at small a (Lube; Lajeunesse)
LAMBDA_SPREAD = 0.30             # the sources disagree by "tens of percent"
SMALL_A_MAX = 1.0                # the linear fit uses a <= SMALL_A_MAX
LINEAR_END = 1.8                 # Lube et al. (2005, planar): 1.2 a below a = 1.8 ...
POWER_COEFFICIENT = 1.9          # ... and 1.9 a^(2/3) above a = 2.8
POWER_EXPONENT = 2.0 / 3.0
POWER_START = 2.8
HEIGHT_TRANSITION = 1.15         # Lube et al. (2005): Hf/L0 = a below 1.15, a^(2/5) above
HEIGHT_EXPONENT = 0.4
MAST_OVERPREDICTION = 0.40       # MPM with Mohr-Coulomb, a > 2 (Mast et al. 2014)


# One-off runs made while writing this check (not repeated by it; mpm_geo 0.1.0 as built on
# 2026-11-25 23:05, the Bui case with APIC and separation).
RESOLUTION_NOTE = (
    "Cell size (one-off runs while this check was written, 2026-11-25, not repeated by it): "
    "(Lf - L0)/L0 at a = 0.5 / at a = 1 / the fitted lambda were 0.97 / 2.20 / 2.15 with 16 "
    "cells over L0 (this sweep), 0.89 / 2.13 / 2.06 with 20 and 0.99 / 2.67 / 2.53 with 24; "
    "with 32 cells a = 0.5 gave 1.09 (toe 5 % short of the Bui experiment). Hf/L0 at a = 0.5 "
    "was 0.50 at every size. lambda stays between 2.0 and 2.6, near the Bui experiment's 2.42 "
    "and above the published band, at every resolution tried.")
BUILD_NOTE = (
    "The contiguous toe of a long one-particle sheet is fragile: between two builds of "
    "2026-11-25 that differ in the averaging of the frictional floor's normal impulse (commit "
    "25e652e), (Lf - L0)/L0 moved from 2.51 to 2.20 at a = 1, 5.09 to 6.09 at a = 2 and 8.17 to "
    "8.52 at a = 3, while the toe at least one cell thick (2.04 / 3.30 / 6.53 to 2.11 / 3.29 / "
    "6.44) and the farthest particle (3.05 / 7.23 / 10.32 to 3.04 / 7.15 / 10.44) moved by less "
    "than 4 %: read the runouts to about 20 %, where the sheet happens to tear.")

WHAT_THE_MODEL_MISSES = [
    "The material is the Bui et al. (2008) aluminium-bar continuum (phi = 19.8 deg, floor "
    "mu = 0.36), far less frictional than the sands and glass beads of the published sweeps; its "
    "own experiment ran out 1.21 L0 at a = 0.5, twice the sand trend 1.2 a. The published "
    "coefficients are therefore a trend for another material: a lower friction lengthens the "
    "runout at every a and lowers the aspect ratio below which the top of the column survives.",
    "Side walls: the published runs are in channels a few cm wide whose wall friction slows the "
    "flow; plane strain has none (and the wall at x = 0 is frictionless here), which lengthens "
    "the runout.",
    "Rate independence: Mohr-Coulomb has the same friction in the fast thin front as in the slow "
    "deposit (no mu(I) rheology); the front keeps spreading as a one-particle sheet, one reason "
    "for the long runouts at large a (Mast et al. 2014).",
    "Grain scale: the thinnest layer is one particle (dx / ppc = 6 mm), far thicker than a grain; "
    "the contiguous toe depends on how that sheet tears.",
    "A numerical defect, not physics: particles of the thin front lying on the frictional floor "
    "can grow without bound in area and are then thrown up (see the inflated-particle target); "
    "the measures leave them out.",
]


# ---------------------------------------------------------------------------------------------
# set-up
# ---------------------------------------------------------------------------------------------

def published_runout(a):
    """Upper envelope of the published runouts (Lf - L0)/L0 at aspect ratio ``a``."""
    return max(LAMBDA_PUBLISHED[1] * a, POWER_COEFFICIENT * a ** POWER_EXPONENT)


def run_name(a, tag=""):
    return f"aspect_ratio_a{a:g}{tag}"


def _cells(length, dx, what):
    cells = length / dx
    if abs(cells - round(cells)) > 1e-6:
        raise ValueError(f"{what} {length:g} m is not a whole number of {dx:g} m cells")
    return int(round(cells))


def gravity_magnitude(case):
    return float(np.linalg.norm(case.get("gravity", [0.0, 0.0])))


def sweep_case(bui, a, cells=CELLS_PER_WIDTH, tag=""):
    """The case of aspect ratio ``a``: geometry here, everything else from the Bui case;
    ``cells`` over L0, ``tag`` appended to the run's name."""
    dx = COLUMN_WIDTH / cells
    width, height = COLUMN_WIDTH, a * COLUMN_WIDTH
    _cells(width, dx, "column width")
    _cells(height, dx, "column height")    # the column must fill whole cells
    length = width * (1.0 + DOMAIN_MARGIN * published_runout(a))
    g = gravity_magnitude(bui)
    if not g > 0.0:
        raise ValueError(f"{BUI_CASE}: no gravity")
    boundaries = copy.deepcopy(bui["domain"].get("boundaries", {}))
    boundaries["ymax"] = "sliding"         # see HEIGHT_MARGIN
    material = copy.deepcopy(bui["materials"][0])
    time = {k: v for k, v in bui.get("time", {}).items() if k != "tend"}
    time["tend"] = round(FLOW_TIMES * math.sqrt(height / g) + REST_WINDOW, 3)
    return {
        "name": run_name(a, tag),
        "domain": {"nx": int(math.ceil(length / dx - 1e-9)),
                   "ny": int(math.ceil(HEIGHT_MARGIN * height / dx - 1e-9)),
                   "dx": dx, "boundaries": boundaries},
        "particles": copy.deepcopy(bui.get("particles", {})),
        "materials": [material],
        "bodies": [{"name": "column", "material": material["name"],
                    "min": [0.0, 0.0], "max": [width, height]}],
        "gravity": copy.deepcopy(bui["gravity"]),
        "solver": copy.deepcopy(bui.get("solver", {})),
        "time": time,
        "output": {"interval": OUTPUT_INTERVAL,
                   "fields": ["position", "displacement", "velocity", "material", "mass",
                              "volume"]},
    }


def copied_parts(case):
    """The parts of a sweep case that come from the Bui case (to detect a changed Bui case)."""
    boundaries = {k: v for k, v in case["domain"].get("boundaries", {}).items() if k != "ymax"}
    time = {k: v for k, v in case.get("time", {}).items() if k != "tend"}
    return {"material": case["materials"][0], "boundaries": boundaries,
            "particles": case.get("particles", {}), "gravity": case.get("gravity"),
            "solver": case.get("solver", {}), "time": time}


def describe_face(value):
    if isinstance(value, dict):
        if value.get("type", "").lower() == "frictional":
            return f"frictional, mu = {value['mu']:g}"
        return value.get("type", "free")
    return value


def material_text(material):
    return f"{material['type']}: " + ", ".join(
        f"{k} = {v}" for k, v in material.items() if k not in ("type", "name"))


def setup_rows(cases, bui):
    first = next(iter(cases.values()))
    dx = first["domain"]["dx"]
    ppc = first.get("particles", {}).get("ppc", 2)
    faces = first["domain"]["boundaries"]
    dims = "; ".join(
        f"a = {a:g}: {c['domain']['nx']} x {c['domain']['ny']} cells "
        f"({c['domain']['nx'] * dx:.3g} x {c['domain']['ny'] * dx:.3g} m), "
        f"t = {c['time']['tend']:g} s" for a, c in cases.items())
    return [
        ["columns", f"L0 = {COLUMN_WIDTH:g} m wide (the Bui column), H0 = a L0 high, "
                    f"a = {', '.join(f'{a:g}' for a in cases)}; against the wall x = 0, "
                    "released at t = 0"],
        ["cells", f"{dx * 1e3:g} mm ({CELLS_PER_WIDTH} over L0), {ppc} particles per cell and "
                  f"axis: {CELLS_PER_WIDTH ** 2 * ppc ** 2} a particles"],
        ["domains and end times", dims + f"; length L0 (1 + {DOMAIN_MARGIN:g} R_env(a)), "
         "R_env = max(1.35 a, 1.9 a^(2/3)); height 1.2 H0; end time 7 sqrt(H0/g) + 0.1 s"],
        ["material", material_text(first["materials"][0])],
        ["floor", str(describe_face(faces.get("ymin", "free")))],
        ["other faces", ", ".join(f"{k} {describe_face(v)}" for k, v in faces.items()
                                  if k != "ymin") + " (the top closed here, free in the Bui "
                                                    "case: see the notes)"],
        ["solver", ", ".join(f"{k} {v}" for k, v in first.get("solver", {}).items())],
        ["time step", ", ".join(f"{k} {v}" for k, v in first["time"].items() if k != "tend")],
        ["taken from the Bui case", f"`{relative(BUI_CASE)}` at run time: materials[0], "
         "domain.boundaries (top face excepted), particles, gravity, solver, time (without tend)"],
    ]


# ---------------------------------------------------------------------------------------------
# run
# ---------------------------------------------------------------------------------------------

def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_case(exe, case, output, overwrite, quiet):
    """Run mpm_geo on ``case`` into ``output`` (the case is kept there).

    Returns (wall time, CPU time) [s]: the CPU time of the mpm_geo process shows the cost when
    other programs share the cores and stretch the wall time.
    """
    output = Path(output)
    case_path = output.parent / f".{case['name']}.json"
    output.parent.mkdir(parents=True, exist_ok=True)
    case_path.write_text(json.dumps(case, indent=2) + "\n", encoding="utf-8")
    cpu = _children_cpu()
    try:
        wall = run_mpm_geo(exe, case_path, output, overwrite, quiet, cwd=REPO)
        cpu = _children_cpu() - cpu
    finally:
        if output.is_dir():
            (output / CASE_FILE).write_text(json.dumps(case, indent=2) + "\n", encoding="utf-8")
        case_path.unlink(missing_ok=True)
    return wall, cpu


# ---------------------------------------------------------------------------------------------
# analysis
# ---------------------------------------------------------------------------------------------

def experiment():
    """Figures of the Bui et al. (2008) experiment (a = 0.5, the same material)."""
    xs, hs = load_reference_profile(BUI_SURFACE)
    xf, hf = load_reference_profile(BUI_FAILURE)
    return {"runout": (float(xs[-1]) - BUI_WIDTH) / BUI_WIDTH,
            "height": float(hs[np.argmin(xs)]) / BUI_WIDTH,
            "slip_angle_deg": slip_angle(xf, hf),
            "aspect_ratio": 0.5}


def _healthy(volume, volume0):
    return np.isfinite(volume) & (volume > 0.0) & (volume <= INFLATION_LIMIT * volume0)


def analyse(run_dir, case, a):
    """Figures of the last output of one run; returns (metrics, arrays for the plots)."""
    outputs = list_outputs(run_dir)
    if not outputs:
        raise FileNotFoundError(f"no particles_NNNNNN.h5 output in {run_dir}")
    frames = [load_particles(path) for _, path in outputs]
    for field in ("volume", "mass"):
        if field not in frames[-1]:
            raise ValueError(f"{frames[-1]['path']}: field '{field}' missing")
    first, last = frames[0], frames[-1]
    times = np.array([f["time"] for f in frames])
    before = frames[int(np.argmin(np.abs(times - (last["time"] - REST_WINDOW))))]
    volume0 = first["volume"]
    dx = case["domain"]["dx"]
    length = case["domain"]["nx"] * dx
    width = case["bodies"][0]["max"][0] - case["bodies"][0]["min"][0]
    height0 = case["bodies"][0]["max"][1] - case["bodies"][0]["min"][1]

    # broken (inflated) particles, over the whole run and at the end
    broken = [np.count_nonzero(~_healthy(f["volume"], volume0)) for f in frames]
    growth = max(float(np.max(np.where(np.isfinite(f["volume"]), f["volume"], np.inf)
                              / volume0)) for f in frames)
    first_broken = next((f["time"] for f, n in zip(frames, broken) if n > 0), None)
    ok = _healthy(last["volume"], volume0)
    ok_window = ok & _healthy(before["volume"], volume0)

    pos = last["position"]
    x, y = pos[ok, 0], pos[ok, 1]
    half = particle_half_size(last["volume"][ok], 2)
    toe = toe_position(x, y, half)
    toe_cell = toe_position(x, y, half, min_height=dx)
    final_height = max_height(x, y, half, x_max=toe)
    wall_height = height_at_wall(x, y, half)
    farthest = float(np.max(x + half))     # healthy particles only, detached ones included

    # at rest: from which output on every healthy particle stays within dx/2 of its end position
    rest_time = last["time"]
    for frame in reversed(frames):
        keep = ok & _healthy(frame["volume"], volume0)
        move = np.linalg.norm(frame["position"][keep] - pos[keep], axis=1)
        if move.size and np.max(move) >= 0.5 * dx:
            break
        rest_time = frame["time"]

    history = load_history(run_dir)
    kinetic = history.get("kinetic_energy", np.zeros(0))
    kinetic_ratio = (float(kinetic[-1] / kinetic.max())
                     if kinetic.size and np.isfinite(kinetic).all() and kinetic.max() > 0
                     else None)
    mass0, mass1 = float(np.sum(first["mass"])), float(np.sum(last["mass"]))
    volume_ok0 = float(np.sum(volume0[ok]))
    metrics = {
        "aspect_ratio": a,
        "initial_width_m": width,
        "initial_height_m": height0,
        "time_s": last["time"],
        "particles": int(pos.shape[0]),
        "toe_m": toe,
        "runout_ratio": (toe - width) / width,
        "toe_one_cell_thick_m": toe_cell,
        "runout_ratio_one_cell_thick": (toe_cell - width) / width,
        "farthest_particle_m": farthest,
        "runout_ratio_farthest": (farthest - width) / width,
        "final_height_m": final_height,
        "final_height_ratio": final_height / width,
        "height_at_wall_m": wall_height,
        "height_at_wall_ratio": wall_height / width,
        "domain_length_m": length,
        "end_wall_clearance_m": length - farthest,
        "deposit_reaches_end_wall": bool(farthest >= length - dx),
        "max_move_last_window_m": float(np.max(np.linalg.norm(
            pos[ok_window] - before["position"][ok_window], axis=1))),
        "rest_window_s": last["time"] - before["time"],
        "at_rest_from_s": rest_time,
        "kinetic_final_over_peak": kinetic_ratio,
        "largest_area_growth": growth,
        "inflated_particles_final": int(broken[-1]),
        "inflated_particles_max": int(max(broken)),
        "inflated_first_time_s": first_broken,
        "inflated_mass_fraction_final": float(np.sum(last["mass"][~ok]) / mass1),
        "mass_relative_change": (mass1 - mass0) / mass0,
        "volume_relative_change": float(np.sum(last["volume"][ok]) / volume_ok0 - 1.0),
    }
    xc, surface = free_surface(x, y, half, bin_edges(0.0, length, dx))
    arrays = {"xc": xc, "surface": surface, "width": width, "height": height0}
    return metrics, arrays


def fit_through_origin(a, r):
    a, r = np.asarray(a, float), np.asarray(r, float)
    return float(np.sum(a * r) / np.sum(a * a))


def compare(runs, exp, dx):
    """Targets (gating) and reported comparisons over the sweep; returns (targets, summary)."""
    a = np.array(sorted(runs))
    r = np.array([runs[k]["runout_ratio"] for k in a])
    cell = dx / COLUMN_WIDTH
    low = LAMBDA_PUBLISHED[0] * (1.0 - LAMBDA_SPREAD)
    high = LAMBDA_PUBLISHED[1] * (1.0 + LAMBDA_SPREAD)
    small = a <= SMALL_A_MAX + 1e-9
    slope = fit_through_origin(a[small], r[small]) if np.any(small) else float("nan")
    steps = np.diff(r)
    smallest_step = float(np.min(steps)) if steps.size else float("nan")
    material_factor = exp["runout"] / (LAMBDA_PUBLISHED[0] * exp["aspect_ratio"])
    summary = {"runout_slope_small_a": slope, "runout_slope_band": [low, high],
               "smallest_runout_step": smallest_step,
               "material_factor": material_factor,
               "bui_runout_ratio": exp["runout"], "bui_height_ratio": exp["height"],
               "bui_slip_angle_deg": exp["slip_angle_deg"]}
    results = [
        target("runout grows with a", smallest_step, None, "every step > 0",
               steps.size > 0 and bool(np.all(steps > 0.0)), True,
               "published trend; the smallest increase of (Lf - L0)/L0 from one a to the next"),
        target(f"runout / a, fit over a <= {SMALL_A_MAX:g}", slope, None,
               f"{low:.2f} to {high:.2f}", low <= slope <= high, False,
               "reported, not gating: REFERENCES.md section 5 asks for a trend check, not an "
               "exact target, and the coefficient belongs to sand and glass beads, not to this "
               "material; published lambda 1.2 (Lube et al. 2005) to 1.35, "
               f"widened by {LAMBDA_SPREAD:.0%} each way because the sources and materials "
               "disagree by tens of percent; least-squares line through the origin. The same "
               f"material's experiment (Bui, a = 0.5) gives {exp['runout'] / 0.5:.2f}, outside "
               "this band too: the band describes sand and glass beads"),
    ]
    if 0.5 in runs:
        run = runs[0.5]
        error = (run["toe_m"] - (1.0 + exp["runout"]) * COLUMN_WIDTH) / \
            ((1.0 + exp["runout"]) * COLUMN_WIDTH)
        summary["bui_toe_relative_error"] = error
        results.append(target(
            "runout at a = 0.5 (Bui experiment)", run["runout_ratio"], exp["runout"],
            "toe within 15 %", abs(error) <= 0.15, False,
            "the same material and geometry measured (Bui et al. 2008); 15 % is the band of the "
            f"bui2008 5 mm copy, these cells are {dx * 1e3:g} mm; toe error "
            f"{error:+.0%}"))
        results.append(target(
            "final height at a = 0.5", run["final_height_ratio"], 0.5,
            f"0.5 +- {cell:.4g} (one cell)", abs(run["final_height_ratio"] - 0.5) <= cell, True,
            "Hf = H0 while the failure surface leaves the top at the wall untouched: Hf/L0 = a "
            f"below a = {HEIGHT_TRANSITION:g} (Lube et al. 2005), and below tan(slip angle) = "
            f"{math.tan(math.radians(exp['slip_angle_deg'])):.2f} for the failure surface "
            f"measured with this material ({exp['slip_angle_deg']:.1f} deg); one cell: the top "
            "of a particle cloud is known to about a cell, the elastic settlement is < 0.2 mm"))
    if 1.0 in runs:
        run = runs[1.0]
        results.append(target(
            "final height at a = 1", run["final_height_ratio"], 1.0,
            f"1 +- {cell:.4g} (one cell)", abs(run["final_height_ratio"] - 1.0) <= cell, False,
            f"reported: Hf/L0 = a holds to a = {HEIGHT_TRANSITION:g} for sand (Lube), but a "
            f"failure surface dipping {exp['slip_angle_deg']:.1f} deg as measured with this "
            f"material reaches the wall at {math.tan(math.radians(exp['slip_angle_deg'])):.2f} "
            "L0, below the top of an a = 1 column"))
    large = [k for k in a if k >= 2.0 - 1e-9]
    for k in large:
        trend = POWER_COEFFICIENT * k ** POWER_EXPONENT
        over = runs[k]["runout_ratio"] / trend - 1.0
        summary[f"overprediction_a{k:g}"] = over
        summary[f"overprediction_material_a{k:g}"] = \
            runs[k]["runout_ratio"] / (material_factor * trend) - 1.0
    if large:
        k = max(large)
        over = summary[f"overprediction_a{k:g}"]
        results.append(target(
            f"over-prediction at a = {k:g} (1.9 a^(2/3))", over, MAST_OVERPREDICTION,
            f"<= +{MAST_OVERPREDICTION:.0%} (Mast et al. 2014)", over <= MAST_OVERPREDICTION,
            False,
            f"reported: (Lf - L0)/L0 = {runs[k]['runout_ratio']:.2f} against the a^(2/3) branch "
            f"{POWER_COEFFICIENT * k ** POWER_EXPONENT:.2f} of Lube et al. (2005); MPM with "
            "Mohr-Coulomb is known to run out about 40 % too far at a > 2", unit="%"))
        over_m = summary[f"overprediction_material_a{k:g}"]
        results.append(target(
            f"over-prediction at a = {k:g}, branch scaled to the material", over_m,
            MAST_OVERPREDICTION, f"<= +{MAST_OVERPREDICTION:.0%} (Mast et al. 2014)",
            over_m <= MAST_OVERPREDICTION, False,
            f"reported: the a^(2/3) branch times {material_factor:.2f}, the ratio of the Bui "
            "experiment's runout at a = 0.5 to the sand trend 1.2 a (an estimate: it assumes "
            "the material changes the coefficient and not the exponent, as Balmforth and "
            "Kerswell 2005 report for their materials)", unit="%"))
    if len(large) >= 2:
        k0, k1 = large[-2], large[-1]
        exponent = math.log(runs[k1]["runout_ratio"] / runs[k0]["runout_ratio"]) / \
            math.log(k1 / k0)
        summary["runout_exponent_large_a"] = exponent
        results.append(target(
            f"runout exponent, a = {k0:g} to {k1:g}", exponent, POWER_EXPONENT, "2/3 +- 0.15",
            abs(exponent - POWER_EXPONENT) <= 0.15, False,
            "reported: log-log slope between the two largest a; two points and a transition "
            "near a = 2-3 make it a rough figure"))
    results += [
        target("at rest (every run)", max(run["max_move_last_window_m"] for run in runs.values()),
               None, f"largest move over the last {REST_WINDOW:g} s < dx/2 = "
                     f"{0.5 * dx * 1e3:g} mm", all(run["max_move_last_window_m"] < 0.5 * dx
                                                   for run in runs.values()), True,
               "a runout means something only once the deposit has stopped; judged on "
               "positions (largest over the runs, broken particles left out)", unit="mm"),
        target("clear of the end wall (every run)",
               min(run["end_wall_clearance_m"] for run in runs.values()), None, f"> dx",
               not any(run["deposit_reaches_end_wall"] for run in runs.values()), True,
               "a deposit stopped by the end wall has no runout; smallest distance between a "
               "particle and the end of the domain over the runs (lengthen DOMAIN_MARGIN if it "
               "fails)", unit="m"),
        target("inflated particles (every run)",
               float(max(run["inflated_particles_max"] for run in runs.values())), 0.0,
               f"none above {INFLATION_LIMIT:g} V0", all(run["inflated_particles_max"] == 0
                                                          for run in runs.values()), True,
               "numerical defect: a particle area growing without bound (to 1e7-1e20 V0) is no "
               "granular dilation; largest number of such particles at one output over the "
               "runs; they are left out of every other figure. The limit is twice the largest "
               f"growth of healthy front particles (about 4 at a = 3; largest in these runs: "
               f"{max(run.get('largest_area_growth', float('nan')) for run in runs.values()):.2f})"),
    ]
    return results, summary


# ---------------------------------------------------------------------------------------------
# plots
# ---------------------------------------------------------------------------------------------

def _log_axes(axes, yticks):
    from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator, ScalarFormatter
    axes.set_xscale("log")
    axes.set_yscale("log")
    for axis, ticks in ((axes.xaxis, (0.5, 1, 1.5, 2, 3, 4)), (axes.yaxis, yticks)):
        axis.set_major_locator(FixedLocator(ticks))
        axis.set_major_formatter(ScalarFormatter())
        axis.set_minor_locator(NullLocator())
        axis.set_minor_formatter(NullFormatter())
    axes.grid(True, lw=0.3, alpha=0.5)


def plot_trends(path, runs, summary, exp, dx):
    a = np.array(sorted(runs))
    r = np.array([runs[k]["runout_ratio"] for k in a])
    r_far = np.array([runs[k]["runout_ratio_farthest"] for k in a])
    r_cell = np.array([runs[k]["runout_ratio_one_cell_thick"] for k in a])
    hf = np.array([runs[k]["final_height_ratio"] for k in a])
    hw = np.array([runs[k]["height_at_wall_ratio"] for k in a])
    grid = np.geomspace(0.3, 4.0, 200)
    figure = agg_figure(10.0, 5.6)
    left, right = figure.subplots(1, 2)

    low, high = summary["runout_slope_band"]
    fit = grid <= 1.2
    left.fill_between(grid[fit], low * grid[fit], high * grid[fit], color="tab:blue",
                      alpha=0.12, label=f"band of the fit: {low:.2f}-{high:.2f} a")
    lin = grid <= LINEAR_END
    left.plot(grid[lin], 1.2 * grid[lin], color="tab:blue", lw=1.4,
              label="Lube et al. 2005: 1.2 a (a < 1.8)")
    left.plot(grid[~lin], 1.2 * grid[~lin], color="tab:blue", lw=0.8, ls=":")
    left.plot(grid[lin], 1.35 * grid[lin], color="tab:cyan", lw=1.0, ls="--",
              label="1.35 a (upper published lambda)")
    power = POWER_COEFFICIENT * grid ** POWER_EXPONENT
    big = grid >= POWER_START
    left.plot(grid[big], power[big], color="tab:red", lw=1.4,
              label="Lube et al. 2005: 1.9 a^(2/3) (a > 2.8)")
    left.plot(grid[~big], power[~big], color="tab:red", lw=0.8, ls=":")
    left.plot(grid, summary["material_factor"] * power, color="tab:red", lw=1.0, ls="-.",
              label=f"1.9 a^(2/3) x {summary['material_factor']:.2f} (scaled to the Bui point)")
    left.plot(grid, (1.0 + MAST_OVERPREDICTION) * power, color="tab:orange", lw=0.8, ls="--",
              label="+40 % (Mast et al. 2014)")
    left.plot(grid[fit], summary["runout_slope_small_a"] * grid[fit], color="black", lw=0.8,
              ls="--", label=f"model fit over a <= {SMALL_A_MAX:g}: "
                             f"{summary['runout_slope_small_a']:.2f} a")
    left.plot(a, r, "o-", color="black", label="model: contiguous toe")
    left.plot(a, r_far, "x", color="0.45", label="model: farthest particle")
    left.plot(a, r_cell, "+", color="0.45", ms=8, label="model: toe at least one cell thick")
    left.plot([exp["aspect_ratio"]], [exp["runout"]], "*", color="tab:green", ms=12,
              label="Bui et al. 2008 experiment")
    _log_axes(left, (0.5, 1, 2, 3, 5, 10))
    left.set_xlabel("a = H0 / L0")
    left.set_ylabel("(Lf - L0) / L0")
    left.set_title("normalised runout", fontsize=9)
    left.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2,
                frameon=False)

    cell = dx / COLUMN_WIDTH
    below = grid <= HEIGHT_TRANSITION
    right.fill_between(grid[below], grid[below] - cell, grid[below] + cell, color="tab:blue",
                       alpha=0.12, label="Hf = H0 +- one cell")
    right.plot(grid[below], grid[below], color="tab:blue", lw=1.4,
               label="Lube et al. 2005: Hf/L0 = a (a < 1.15)")
    right.plot(grid[~below], grid[~below] ** HEIGHT_EXPONENT, color="tab:red", lw=1.4,
               label="Lube et al. 2005: a^(2/5) (a > 1.15)")
    slip = math.tan(math.radians(exp["slip_angle_deg"]))
    right.axhline(slip, color="tab:green", lw=0.8, ls="--",
                  label=f"Hf/L0 = tan {exp['slip_angle_deg']:.1f} deg: the Bui slip line "
                        "through the toe meets the wall")
    right.plot(a, hf, "o-", color="black", label="model: largest height")
    right.plot(a, hw, "s", mfc="none", color="0.4", label="model: height at the wall")
    right.plot([exp["aspect_ratio"]], [exp["height"]], "*", color="tab:green", ms=12,
               label="Bui et al. 2008 experiment")
    _log_axes(right, (0.3, 0.5, 0.7, 1, 1.5, 2))
    right.set_xlabel("a = H0 / L0")
    right.set_ylabel("Hf / L0")
    right.set_title("final height", fontsize=9)
    right.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2,
                 frameon=False)
    figure.suptitle(f"Column collapse against the aspect ratio, {dx * 1e3:g} mm cells "
                    f"(L0 = {COLUMN_WIDTH:g} m, Bui et al. 2008 material)", fontsize=10)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def plot_profiles(path, runs, arrays, dx):
    figure = agg_figure(10.0, 5.0)
    axes = figure.add_subplot()
    colours = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown",
               "tab:pink", "tab:gray")
    right = 0.0
    for (a, arr), colour in zip(sorted(arrays.items()), colours):
        width = arr["width"]
        xc, surface = arr["xc"] / width, arr["surface"] / width
        filled = surface > 0.0
        axes.plot(xc[filled], surface[filled], color=colour, lw=1.1,
                  label=f"a = {a:g}: (Lf - L0)/L0 = {runs[a]['runout_ratio']:.2f}, "
                        f"Hf/L0 = {runs[a]['final_height_ratio']:.2f}")
        axes.plot([0, 1, 1], [a, a, 0], color=colour, lw=0.7, ls=":")
        toe = runs[a]["toe_m"] / width
        axes.plot([toe], [0.0], "v", color=colour, ms=6)
        right = max(right, float(xc[filled].max()) if np.any(filled) else 0.0)
    axes.set_xlim(0.0, right + 0.3)
    axes.set_ylim(0.0, max(arrays) * 1.05)
    axes.set_aspect(2.0)
    axes.set_xlabel("x / L0")
    axes.set_ylabel("y / L0")
    axes.set_title(f"Final free surfaces (highest particle top per {dx * 1e3:g} mm bin; "
                   "dotted: initial columns; triangles: contiguous toes; vertical scale x 2)",
                   fontsize=9)
    axes.legend(fontsize=7, loc="upper right")
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


# ---------------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------------

def _num(value, digits=2):
    return "n/a" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def per_a_table(runs, walls, failures, dx):
    header = ["a", "particles", "domain [m]", "end time [s]", "(Lf - L0)/L0",
              "1.2 a / 1.9 a^(2/3)", "model over 1.9 a^(2/3)", "one cell thick",
              "farthest particle", "Hf/L0", "at the wall", "at rest from [s]",
              "move, last 0.1 s [mm]", "KE end / peak", "volume change",
              "largest particle growth V/V0", "inflated (max)", "mpm_geo wall / CPU [s]"]
    rows = []
    for a in sorted(set(runs) | set(failures)):
        wall = walls.get(a)
        wall_text = "n/a" if wall is None else f"{wall[0]:.0f} / {wall[1]:.0f}"
        if a in failures:
            rows.append([f"{a:g}"] + ["-"] * (len(header) - 3) + [f"run failed: "
                                                                 f"{failures[a]}", wall_text])
            continue
        m = runs[a]
        trend = f"{1.2 * a:.2f} / {POWER_COEFFICIENT * a ** POWER_EXPONENT:.2f}"
        kinetic = m["kinetic_final_over_peak"]
        rows.append([
            f"{a:g}", m["particles"], f"{m['domain_length_m']:.3g}", f"{m['time_s']:.3g}",
            f"**{_num(m['runout_ratio'])}**", trend,
            f"{m['runout_ratio'] / (POWER_COEFFICIENT * a ** POWER_EXPONENT) - 1.0:+.0%}",
            _num(m["runout_ratio_one_cell_thick"]),
            _num(m["runout_ratio_farthest"]), f"**{_num(m['final_height_ratio'])}**",
            _num(m["height_at_wall_ratio"]), f"{m['at_rest_from_s']:.2f}",
            f"{m['max_move_last_window_m'] * 1e3:.1f}",
            "n/a" if kinetic is None else f"{kinetic:.1e}",
            f"{m['volume_relative_change']:+.1%}",
            f"{m['largest_area_growth']:.2f}" if "largest_area_growth" in m else "n/a",
            f"{m['inflated_particles_max']}"
            + (f" (from {m['inflated_first_time_s']:.2f} s)" if m["inflated_particles_max"]
               else ""),
            wall_text])
    return {"title": f"Per aspect ratio ({dx * 1e3:g} mm cells; runout = contiguous toe; Hf = "
                     "largest height of the contiguous deposit)",
            "header": header, "rows": rows}


def check_copied(case, bui_case, a):
    """Warn when an existing output was run with other Bui settings than the current ones."""
    if copied_parts(case) != copied_parts(bui_case):
        print(f"check.py: warning: the a = {a:g} output was run with other material, faces, "
              f"particles, gravity, solver or time step than {relative(BUI_CASE)} has now; "
              "run again without --no-run", file=sys.stderr)


def sweep(args):
    bui = load_json(BUI_CASE)
    exp = experiment()
    base = Path(args.output) if args.output else REPO / "outputs"
    cases = {a: sweep_case(bui, a) for a in ASPECT_RATIOS}
    dx = cases[ASPECT_RATIOS[0]]["domain"]["dx"]
    runs, arrays, walls, failures = {}, {}, {}, {}
    for a, case in cases.items():
        output = base / case["name"]
        if not args.no_run:
            try:
                walls[a] = run_case(args.exe, case, output, overwrite=args.output is None,
                                    quiet=args.quiet)
            except RuntimeError as exc:
                failures[a] = str(exc)
                print(f"check.py: a = {a:g}: {exc}", file=sys.stderr)
                continue
        else:
            saved = output / CASE_FILE
            if not saved.is_file():
                raise FileNotFoundError(f"{saved} not found: run without --no-run first")
            check_copied(load_json(saved), case, a)
            case = load_json(saved)
            cases[a] = case
        runs[a], arrays[a] = analyse(output, case, a)
        m = runs[a]
        print(f"a = {a:<4g} (Lf - L0)/L0 = {m['runout_ratio']:.2f}  Hf/L0 = "
              f"{m['final_height_ratio']:.2f} (wall {m['height_at_wall_ratio']:.2f})  at rest "
              f"from {m['at_rest_from_s']:.2f} s  inflated {m['inflated_particles_max']}"
              + (f"  mpm_geo {walls[a][0]:.0f} s (CPU {walls[a][1]:.0f} s)" if a in walls
                 else ""), flush=True)
    if len(runs) < 2:
        print("check.py: error: fewer than two runs to compare", file=sys.stderr)
        return 2
    results, summary = compare(runs, exp, dx)
    passed = all(t["passed"] for t in results if t["gating"]) and not failures
    metrics = dict(summary)
    metrics.update({
        "runs": {f"{a:g}": m for a, m in runs.items()},
        "max_move_last_window_m": max(m["max_move_last_window_m"] for m in runs.values()),
        "rest_window_s": REST_WINDOW,
        "deposit_reaches_end_wall": any(m["deposit_reaches_end_wall"] for m in runs.values()),
        "mass_relative_change": max((m["mass_relative_change"] for m in runs.values()),
                                    key=abs),
    })
    results_dir = Path(args.results)
    trends_png = results_dir / "aspect_ratio.png"
    profiles_png = results_dir / "aspect_ratio_profiles.png"
    plot_trends(trends_png, runs, summary, exp, dx)
    plot_profiles(profiles_png, runs, arrays, dx)
    wall_total = sum(w for w, _ in walls.values()) if walls else None
    cpu_total = sum(c for _, c in walls.values()) if walls else None
    notes = [
        "The five cases are generated by check.py from the Bui case (see the set-up); each "
        "run's case is kept as case.json in its output folder, outputs/aspect_ratio_a<a>/.",
        "Runout: the front of the deposit contiguous from the wall (mpm_post.profiles."
        "toe_position, as bui2008); final height: the highest particle top of that deposit "
        "(mpm_post.profiles.max_height); the height at the wall (height_at_wall) is lower at "
        "large a, where the corner of the column slides down the frictionless wall.",
        "The top face is closed (sliding) in these runs, while the Bui case leaves it free: no "
        "deposit comes near it, but particles broken by the volume blow-up (inflated-particle "
        "target) are thrown up and would stop the run with 'left the grid' (seen with the free "
        "top at a = 2 and 3, 10 mm cells, t = 1.4 s).",
        "Published trends: Lube et al. 2005 (planar channel): (Lf - L0)/L0 = 1.2 a below "
        "a = 1.8 and 1.9 a^(2/3) above 2.8, Hf/L0 = a below 1.15 and a^(2/5) above; "
        "lambda up to 1.35 from REFERENCES.md section 5 (Lajeunesse et al. 2005).",
        RESOLUTION_NOTE,
        BUILD_NOTE,
    ]
    if failures:
        notes.append("Failed runs: " + "; ".join(f"a = {a:g}: {msg}"
                                                 for a, msg in failures.items()))
    report = {
        "case": "aspect_ratio",
        "title": "2D granular column collapses over aspect ratios a = 0.5 to 3 against the "
                 "published runout and final-height trends (Lube et al. 2005, Lajeunesse et "
                 "al. 2005)",
        "resolution": "full",
        "heading": f"sweep over a = {', '.join(f'{a:g}' for a in ASPECT_RATIOS)} "
                   f"({dx * 1e3:g} mm cells, L0 = {COLUMN_WIDTH:g} m)",
        "case_files": [relative(BUI_CASE)],
        "setup": {"rows": setup_rows(cases, bui)},
        "metrics": metrics,
        "targets": results,
        "tables": [per_a_table(runs, walls, failures, dx)],
        "passed": passed,
        "wall_time_s": wall_total,
        "cpu_time_s": cpu_total,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "mpm_geo": exe_version(args.exe) if not args.no_run else None,
        "output": relative(base) + "/aspect_ratio_a<a>",
        "plots": [trends_png.name, profiles_png.name],
        "notes": notes,
        "what_the_model_misses": WHAT_THE_MODEL_MISSES,
    }
    write_json(results_dir / "metrics.json", report, str_keys=True)
    print_table(results, (48, 9, 9, 30))
    print(f"wrote {results_dir / 'metrics.json'}, {trends_png} and {profiles_png}")
    if failures:
        print("aspect_ratio: FAIL (a run failed)")
        return 2
    print(f"aspect_ratio: {'PASS' if passed else 'FAIL (a target is missed)'}")
    return 0 if passed else 1


# --- the sand sweep (--sand) ---------------------------------------------------------------
SAND_PHI = 30.0                  # [deg] the sweep: Mohr-Coulomb, phi = 30 deg, c = 0
SAND_RATIOS = (1.0, 2.0, 3.0)    # the aspect ratios of the goal of issue 19
SAND_CELLS = (16, 32)            # cells over L0: 12.5 and 6.25 mm
SAND_BAND = 0.30                 # the goal: within 30 % of Lube et al. (2005)


def lube_runout(a):
    """(Lf - L0)/L0 of Lube et al. (2005, planar) at aspect ratio ``a``: (low, high). 1.2 a
    below LINEAR_END, 1.9 a^(2/3) above POWER_START; in the transition between, the range of the
    two branches."""
    linear = LAMBDA_PUBLISHED[0] * a
    power = POWER_COEFFICIENT * a ** POWER_EXPONENT
    if a <= LINEAR_END:
        return linear, linear
    if a >= POWER_START:
        return power, power
    return min(linear, power), max(linear, power)


def sand_case(bui, a, cells):
    """The sweep case of ``a`` with ``cells`` over L0 in the sand: the Bui material with
    phi = SAND_PHI (psi = 0, c = 0 as there) on a frictional floor of mu = tan(phi)."""
    case = sweep_case(bui, a, cells, tag=f"_sand{cells}")
    case["materials"][0]["phi"] = SAND_PHI
    mu = round(math.tan(math.radians(SAND_PHI)), 4)
    case["domain"]["boundaries"]["ymin"] = {"type": "frictional", "mu": mu}
    # the sand runs out less far than the bars: the same domain rule holds with margin
    return case


def sand_sweep(args):
    """Run (or read) the sand columns at both resolutions and compare them with Lube et al."""
    bui = load_json(BUI_CASE)
    base = Path(args.output) if args.output else REPO / "outputs"
    rows, targets, walls = [], [], []
    for cells in SAND_CELLS:
        for a in SAND_RATIOS:
            case = sand_case(bui, a, cells)
            output = base / case["name"]
            wall = None
            if not args.no_run:
                wall = run_case(args.exe, case, output, overwrite=args.output is None,
                                quiet=args.quiet)
            else:
                saved = output / CASE_FILE
                if not saved.is_file():
                    raise FileNotFoundError(f"{saved} not found: run without --no-run first")
            m, _ = analyse(output, case, a)
            low, high = lube_runout(a)
            m.update({"cells_per_width": cells, "dx_m": case["domain"]["dx"],
                      "lube_low": low, "lube_high": high})
            rows.append(m)
            walls.append(wall)
            dx = f"{case['domain']['dx'] * 1e3:g} mm"
            published = f"{low:.2f}" if low == high else f"{low:.2f}-{high:.2f}"
            targets.append(target(
                f"(Lf - L0)/L0 at a = {a:g}, {dx} cells", m["runout_ratio"], high,
                f"{(1 - SAND_BAND) * low:.2f} .. {(1 + SAND_BAND) * high:.2f}",
                (1 - SAND_BAND) * low <= m["runout_ratio"] <= (1 + SAND_BAND) * high, False,
                f"goal of issue 19: within {SAND_BAND:.0%} of Lube et al. (2005), {published}"
                + (" (the range of the two branches in the transition)" if low != high else "")))
            targets.append(target(
                f"no inflated particle, a = {a:g}, {dx} cells",
                float(m["inflated_particles_max"]), 0.0, "0",
                m["inflated_particles_max"] == 0, False,
                f"particles above {INFLATION_LIMIT:g} times their area at any output "
                f"(largest growth {m['largest_area_growth']:.1f})"))
    by = {(r["cells_per_width"], r["aspect_ratio"]): r for r in rows}
    change = []
    for a in SAND_RATIOS:
        coarse, fine = by[(SAND_CELLS[0], a)], by[(SAND_CELLS[1], a)]
        change.append(fine["runout_ratio"] / coarse["runout_ratio"] - 1.0)
    def beyond(r):
        """How far a runout lies outside the published value (or range), relative to it."""
        if r["runout_ratio"] > r["lube_high"]:
            return r["runout_ratio"] / r["lube_high"] - 1.0
        if r["runout_ratio"] < r["lube_low"]:
            return r["runout_ratio"] / r["lube_low"] - 1.0
        return 0.0

    text = "; ".join(
        f"a = {a:g}: " + ", ".join(f"{by[(c, a)]['runout_ratio']:.2f} "
                                   f"({beyond(by[(c, a)]) * 100:+.0f} %)" for c in SAND_CELLS)
        for a in SAND_RATIOS)
    passed = all(t["passed"] for t in targets)
    headline = (f"(Lf - L0)/L0 of the sand columns at {SAND_CELLS[0]} and {SAND_CELLS[1]} cells "
                f"over L0 against Lube et al. (2005) (beyond the published value, or the range "
                f"of its two branches at a = 2): {text}; refinement moves them by "
                + ", ".join(f"{c * 100:+.0f} %" for c in change)
                + f". Goal of issue 19 (within 30 % at two resolutions) "
                  f"{'met' if passed else 'not met'}.")
    table = {"title": "Per column and cell size",
             "header": ["a", "cells over L0", "(Lf - L0)/L0", "Lube et al. (2005)",
                        "one cell thick", "farthest particle", "Hf/L0", "largest area growth",
                        "at rest from", "mpm_geo wall time"],
             "rows": [[f"{r['aspect_ratio']:g}", r["cells_per_width"],
                       f"{r['runout_ratio']:.2f}",
                       f"{r['lube_low']:.2f}" if r["lube_low"] == r["lube_high"] else
                       f"{r['lube_low']:.2f}-{r['lube_high']:.2f}",
                       f"{r['runout_ratio_one_cell_thick']:.2f}",
                       f"{r['runout_ratio_farthest']:.2f}", f"{r['final_height_ratio']:.2f}",
                       f"{r['largest_area_growth']:.1f}", f"{r['at_rest_from_s']:.2f} s",
                       "-" if w is None else f"{w[0]:.0f} s"] for r, w in zip(rows, walls)]}
    setup = {"rows": [
        ["columns", f"L0 = {COLUMN_WIDTH:g} m, H0 = a L0, a = "
                    + ", ".join(f"{a:g}" for a in SAND_RATIOS)
                    + "; the geometry, domains and end times of the sweep above"],
        ["material", f"the Bui case's material with phi = {SAND_PHI:g} deg (psi = 0, c = 0, "
                     "separation as there)"],
        ["floor", f"frictional, mu = tan(phi) = {math.tan(math.radians(SAND_PHI)):.3f} "
                  "(a rough floor)"],
        ["cells", ", ".join(f"{c} over L0 ({COLUMN_WIDTH / c * 1e3:g} mm)" for c in SAND_CELLS)],
        ["solver", "as the Bui case"],
    ]}
    report = {
        "case": "aspect_ratio",
        "title": "2D granular column collapses over aspect ratios a = 0.5 to 3 against the "
                 "published runout and final-height trends (Lube et al. 2005, Lajeunesse et "
                 "al. 2005)",
        "resolution": "sand",
        "heading": "sand columns, a = 1, 2, 3 at two resolutions (reported: the goal of "
                   "issue 19)",
        "headline": headline,
        "reported": True,
        "setup": setup,
        "metrics": {"runs": rows},
        "targets": targets,
        "tables": [table],
        "passed": passed,
        "wall_time_s": sum(w[0] for w in walls) if None not in walls else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "notes": ["Runout: the contiguous toe, as in the sweep above. Lube et al. (2005) "
                  "used sands and glass beads in channels whose side walls slow the flow; "
                  "plane strain has none, which lengthens the runout."],
    }
    results_dir = Path(args.results)
    png = results_dir / "aspect_ratio_sand.png"
    plot_sand(png, rows)
    report["plots"] = [png.name]
    write_json(results_dir / "metrics_sand.json", report, str_keys=True)
    print_table(targets, (48, 9, 9, 30))
    print(headline)
    print(f"wrote {results_dir / 'metrics_sand.json'} and {png}")
    print(f"aspect_ratio (sand): {'PASS' if passed else 'goal not met'} (reported only)")
    return 0 if passed else 1


def plot_sand(path, rows):
    figure = agg_figure(6.0, 4.0)
    axes = figure.add_subplot()
    grid = np.linspace(0.5, 3.5, 61)
    lube = [lube_runout(a) for a in grid]
    axes.fill_between(grid, [(1 - SAND_BAND) * lo for lo, _ in lube],
                      [(1 + SAND_BAND) * hi for _, hi in lube], color="0.85",
                      label=f"Lube et al. (2005) +- {SAND_BAND:.0%}")
    axes.plot(grid, [lo for lo, _ in lube], color="black", lw=0.8)
    axes.plot(grid, [hi for _, hi in lube], color="black", lw=0.8, label="Lube et al. (2005)")
    for cells, marker in zip(SAND_CELLS, ("o", "s")):
        pts = [r for r in rows if r["cells_per_width"] == cells]
        axes.plot([r["aspect_ratio"] for r in pts], [r["runout_ratio"] for r in pts], marker,
                  label=f"mpm-geo, {cells} cells over L0")
    axes.set_xlabel("a = H0 / L0")
    axes.set_ylabel("(Lf - L0) / L0")
    axes.set_title(f"Sand columns (phi = {SAND_PHI:g} deg, rough floor): runout", fontsize=9)
    axes.legend(fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent folder of the run folders aspect_ratio_a<a> (default: "
                                 "outputs/, overwritten); the run folders under a folder given "
                                 "here must not exist")
    parser.add_argument("--sand", action="store_true",
                        help="the sand columns a = 1, 2, 3 at 16 and 32 cells over L0 against "
                             "Lube et al. (2005), reported")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if not args.no_run and exe_missing(args.exe):
        return 2
    try:
        return sand_sweep(args) if args.sand else sweep(args)
    except (OSError, ValueError, RuntimeError, KeyError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
