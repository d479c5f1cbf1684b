#!/usr/bin/env python3
"""Validation: 2D collapse of a column of aluminium bars (Bui et al. 2008).

Runs build/mpm_geo on validation/bui2008/bui2008.json (5 mm cells: the resolution of the issue's
target, a run of a few minutes on 2 cores) or a copy at another resolution, compares the final
deposit with the experiment (data/, see data/README.md) and writes results/metrics*.json and a
plot.

    .venv/bin/python validation/bui2008/check.py              the case file: the issue's targets
    .venv/bin/python validation/bui2008/check.py --refined    2.5 mm cells: convergence, reported
    .venv/bin/python validation/bui2008/check.py --ladder     5, 2.5, 1.25 mm: the refinement
                                                              ladder with derived bands, reported
    .venv/bin/python validation/bui2008/check.py --coarse     regression band (make test)
    .venv/bin/python validation/bui2008/check.py --floors     floor-friction sensitivity
    .venv/bin/python validation/bui2008/check.py --numerics   sensitivity to the numerics
    .venv/bin/python validation/bui2008/check.py --no-run     analyse an existing output

Exit codes: 0 every target met, 1 a target missed, 2 the run or the analysis failed.
Figures compared (targets of the issue in TARGETS below):
- toe: the front of the deposit contiguous from the wall (mpm_post.profiles.toe_position);
- height at the wall, and the RMS / largest difference between the simulated and the measured
  free surface at the measured abscissae;
- the failure surface: the top of the particles that moved less than 1 mm, RMS against the
  measured failure surface, and the dip of a least-squares line through it.
"""

import argparse
import copy
import math
import json
import os
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post import list_outputs, load_history, load_particles  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.study import richardson  # noqa: E402
from mpm_post.profiles import (  # noqa: E402
    bin_edges, failure_surface, free_surface, height_at_wall, load_reference_profile,
    particle_half_size, rms_height_difference, slip_angle, toe_position)
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, exe_version, load_json, print_table, relative,
    write_json)
from mpm_post.validation import target as _target  # noqa: E402

CASE = HERE / "bui2008.json"
DATA = HERE / "data"
SURFACE_FILE = DATA / "Data_Buietal_2008_experimental_surface.txt"
FAILURE_FILE = DATA / "Data_Buietal_2008_experimental_failure_surface.txt"
RESULTS = HERE / "results"
COLUMN_WIDTH = 0.2    # initial column L0 [m]
COLUMN_HEIGHT = 0.1   # initial column H0 [m]
# make test's copy (--coarse) runs at the case's 5 mm with a regression band: at 10 mm the toe
# lands 15 % short (0.376 m; 0.46 m at 5 mm, 0.53 m at 2.5 mm), too near any band.
COARSE_DX = 0.005     # cell of make test's copy [m]
REFINED_DX = 0.0025   # cell of the refined copy (convergence under refinement) [m]
# --ladder: the resolutions of the goal of issue 19 (toe within 5 %, free-surface RMS below
# 3 mm at 5, 2.5 and 1.25 mm with one set of settings), ratio 2, coarse to fine
LADDER_DX = (0.005, 0.0025, 0.00125)
GOAL_SURFACE = 0.003
# The deposit thicker than one cell of the coarsest rung (5 mm, and 0.1 mm so that a particle
# top exactly on it does not count): the part of the deposit every rung resolves, against the
# front of the measured surface at the same thickness.
LADDER_THICKNESS = 0.0051
# Uncertainty of the measured toe: one bar, 1.5 mm (the larger of the two diameters: where the
# last bar of the front lies), on top of the digitisation (about a millimetre, data/README.md);
# of a position on the measured surface, the digitisation.
TOE_UNCERTAINTY = 0.0015
SURFACE_UNCERTAINTY = 0.001
# The bands: toe within 5 % of the measured one, free surface "within a few millimetres"
# RMS (5 mm), height at the wall within one cell of the case (5 mm).
TOE_BAND = 0.05
SURFACE_BAND = 0.005
# make test's coarse copy: a regression band, not the issue target (see compare()).
COARSE_TOE_BAND = 0.15
# A particle is static when it moved less than this [m]: about one bar diameter (1-1.5 mm,
# what an observer of the experiment can see move), three times the largest elastic settlement
# of the column (0.34 mm at the top of the wall), and a twentieth of the slide's displacement.
STATIC_THRESHOLD = 1.0e-3
# The largest particle displacement over the last REST_WINDOW [s] shows whether the deposit
# is at rest in position, whatever the kinetic energy of the particle velocities says.
REST_WINDOW = 0.1

# Variants of the sensitivity studies, each a function of the case returning the
# changed copy, with the label of its row.
# --floors: the case's frictional floor with mu = tan(phi), a no-slip floor and a frictionless
# one (mu = 0: no friction, lift-off allowed, as the frictional floor of the case).
FLOORS = {
    "tan_phi": None,
    "fixed": "fixed",
    "frictionless": {"type": "frictional", "mu": 0.0},
}


def _solver(**changes):
    def apply(case):
        case.setdefault("solver", {}).update(changes)
    return apply


def _material(**changes):
    def apply(case):
        case["materials"][0].update(changes)
    return apply


def _damping(value):
    def apply(case):
        case["solver"]["transfer"] = "flip"
        case["damping"] = {"type": "local", "value": value}
    return apply


# --numerics: the choices of the case file that are numerical rather than physical, one at a
# time: the velocity transfer (APIC in the case; FLIP, pure or blended with PIC), the
# separation of the cohesionless material, the F-bar locking correction, and local damping
# with FLIP (the published GIMP reproduction of Wyser et al. 2021 uses FLIP, local damping 0.05
# and a cell-averaged pressure).
NUMERICS = {
    "case": ("the case file as given", None),
    "flip": ("FLIP transfer (pure)", _solver(transfer="flip")),
    "flip_0.99": ("FLIP with flip_fraction 0.99", _solver(transfer="flip", flip_fraction=0.99)),
    "no_separation": ("separation false", _material(separation=False)),
    "fbar": ("locking_correction fbar", _solver(locking_correction="fbar")),
    "damping": ("FLIP with local damping 0.05", _damping(0.05)),
}


WHAT_THE_MODEL_MISSES = [
    "Convergence of the toe (the ladder, --ladder, part of make validate): the runout grows "
    "under refinement and converges beyond the experiment: 0.4328 m at 5 mm cells (the case "
    "file, -2.2 %), 0.5445 m at 2.5 mm (+23.1 %), 0.5643 m at 1.25 mm (+27.6 %; 51 200 "
    "particles, 6.5 min on 2 cores); the increments shrink (0.112, 0.020 m, observed order "
    "2.5) and the extrapolated toe is 0.569 m, 29 % beyond the measured 0.442 m (2026-12-03). "
    "So the continuum model itself (Mohr-Coulomb, phi = 19.8 deg, psi = 0, c = 0, floor mu = "
    "tan(phi)) over-predicts this runout by about 30 %, as Mast et al. (2014) report for "
    "Mohr-Coulomb collapses, and the agreement at 5 mm comes from the numerical dissipation "
    "of that resolution, not from the physics. The growth is the thin tail: the deposit "
    "thicker than 5.1 mm converges to 0.435 m against 0.396 m measured at that thickness "
    "(+10 %). The numerics table shows how the toe moves with the choices that are numerical "
    "rather than physical; none of them is tuned here.",
    "Grain scale: the bars are a continuum here (Mohr-Coulomb, constant phi, no dilatancy); "
    "the experiment's front ends where the deposit is one or two bars (1-1.5 mm) thick, while "
    "the model's thinnest layer is one particle (dx/2).",
    "Floor friction: the case assumes a bar-on-floor friction of mu = tan(phi) = 0.36; the paper "
    "gives no measured value. The floor sensitivity table shows how much the toe depends on it.",
    "Rate independence: Mohr-Coulomb has no viscosity or mu(I) rheology, so the fast thin front "
    "has the same friction as the slow deposit. A mu(I) material instead (type mu_i; mu_s = "
    "sin(19.8 deg) = 0.339, the zero-rate strength of this case; mu_2 - mu_s = 0.262 and I_0 = "
    "0.279 of the glass beads of Jop et al. 2006, REFERENCES.md section 11, as a stand-in, no "
    "mu(I) being measured for the bars; d = 1.25 mm, the mean bar; rho_s = 2700 kg/m3, "
    "aluminium) halves the growth of the toe under refinement: +3.4 % at 5 mm and +11.7 % at 2.5 "
    "mm (its zero-rate limit, the Drucker-Prager plane-strain cone: -2.1 % and +23.5 %), surface "
    "RMS 1.6 and 1.5 mm, the deposit thicker than 10 mm at 0.3575 and 0.3576 m (-2.8 %). It "
    "misses the 5 % target at 2.5 mm (the sheet thinner than 5 mm still grows, where the "
    "pressure vanishes and mu is at mu_2), so it is a finding of "
    "docs/study/runout_refinement.md, not a validation case.",
    "Final state only: the experiment is compared at rest (t = 1 s); the transient profiles of "
    "the paper's figure (front speed, time to stop) are not checked.",
    "Elastic constants: E = 0.84 MPa is a published modelling value, not a measurement; it only "
    "sets the wave speed and the elastic settlement (0.3 mm), not the deposit.",
    "Volume: with separation the deposit keeps its volume to a few per cent (the experiment's "
    "area grows by 1.5 %); without it every pass of the front through tension adds volume for "
    "good (13-16 % with pure FLIP, about 4 % with APIC: see the numerics table).",
]


# ---------------------------------------------------------------------------------------------
# set-up
# ---------------------------------------------------------------------------------------------

load_case = load_json   # the name bench/study_cases.py and bench/write_study.py use


def coarse_case(case, dx=COARSE_DX, tag="coarse"):
    """A copy of the case with cells of ``dx`` [m] over the same domain, named <case>_<tag>."""
    coarse = copy.deepcopy(case)
    domain = coarse["domain"]
    for axis in ("nx", "ny"):
        length = case["domain"][axis] * case["domain"]["dx"]
        cells = length / dx
        if abs(cells - round(cells)) > 1e-6:
            raise ValueError(f"domain length {length} m along {axis} is not a multiple of {dx} m")
        domain[axis] = int(round(cells))
    domain["dx"] = dx
    coarse["name"] = f"{case['name']}_{tag}"
    return coarse


def with_floor(case, floor):
    """A copy of the case with another floor (ymin) condition, named after it."""
    changed = copy.deepcopy(case)
    if FLOORS[floor] is not None:
        changed["domain"]["boundaries"]["ymin"] = copy.deepcopy(FLOORS[floor])
    # a frictionless floor lets the material reach the end wall and splash up it; a closed top
    # (above the column, never reached otherwise) keeps such a particle in the grid
    changed["domain"]["boundaries"]["ymax"] = "sliding"
    changed["name"] = f"{case['name']}_floor_{floor}"
    return changed


def describe_floor(case):
    ymin = case["domain"].get("boundaries", {}).get("ymin", "free")
    if isinstance(ymin, dict):
        if ymin.get("type", "").lower() == "frictional":
            return f"frictional, mu = {ymin['mu']:g}"
        return ymin.get("type", "free")
    return ymin


def setup_summary(case, nparticles):
    material = case["materials"][0]
    domain = case["domain"]
    ppc = case.get("particles", {}).get("ppc", 2)
    return {
        "dx_m": domain["dx"],
        "cells": [domain["nx"], domain["ny"]],
        "domain_m": [domain["nx"] * domain["dx"], domain["ny"] * domain["dx"]],
        "ppc": ppc,
        "particles": nparticles,
        "material": {k: v for k, v in material.items() if k != "name"},
        "floor": describe_floor(case),
        "walls": {k: v for k, v in domain.get("boundaries", {}).items() if k != "ymin"},
        "solver": case.get("solver", {}),
        "tend_s": case["time"]["tend"],
    }


# ---------------------------------------------------------------------------------------------
# run
# ---------------------------------------------------------------------------------------------

def run_case(exe, case, output, overwrite, quiet):
    """Run mpm_geo on ``case`` (a dict) into ``output``; returns the wall time [s]."""
    with tempfile.TemporaryDirectory(prefix="bui2008_") as tmp:
        case_path = Path(tmp) / f"{case['name']}.json"
        case_path.write_text(json.dumps(case, indent=2), encoding="utf-8")
        return run_mpm_geo(exe, case_path, output, overwrite, quiet, cwd=REPO)


# ---------------------------------------------------------------------------------------------
# analysis
# ---------------------------------------------------------------------------------------------

def experiment():
    """Measured free surface and failure surface, and the figures read off them."""
    xs, hs = load_reference_profile(SURFACE_FILE)
    xf, hf = load_reference_profile(FAILURE_FILE)
    return {
        "surface": (xs, hs), "failure": (xf, hf),
        "toe_m": float(xs[-1]),
        "height_at_wall_m": float(hs[np.argmin(xs)]),
        "slip_angle_deg": slip_angle(xf, hf),
    }


def measured_toe_at(exp, thickness):
    """The front of the measured free surface at ``thickness`` [m]: the first abscissa from the
    wall where the surface falls below it, interpolated linearly between the digitised points."""
    xs, hs = exp["surface"]
    order = np.argsort(xs)
    xs, hs = xs[order], hs[order]
    below = np.nonzero(hs < thickness)[0]
    if below.size == 0:
        return float(xs[-1])
    k = int(below[0])
    if k == 0:
        return float(xs[0])
    t = (hs[k - 1] - thickness) / (hs[k - 1] - hs[k])
    return float(xs[k - 1] + t * (xs[k] - xs[k - 1]))


def analyse(run_dir, case, exp):
    """Figures of the last output of ``run_dir``; returns (metrics, arrays for the plot)."""
    outputs = list_outputs(run_dir)
    if not outputs:
        raise FileNotFoundError(f"no particles_NNNNNN.h5 output in {run_dir}")
    first = load_particles(outputs[0][1])
    last = load_particles(outputs[-1][1])
    before = load_particles(run_dir, time=last["time"] - REST_WINDOW)
    for field in ("displacement", "volume", "mass"):
        if field not in last:
            raise ValueError(f"{last['path']}: field '{field}' missing; the case must write it")
    dx = case["domain"]["dx"]
    length = case["domain"]["nx"] * dx
    x, y = last["position"][:, 0], last["position"][:, 1]
    half = particle_half_size(last["volume"], 2)
    moved = np.linalg.norm(last["displacement"], axis=1)
    edges = bin_edges(0.0, length, dx)   # one cell: see docs/validation.md

    xc, height = free_surface(x, y, half, edges)
    toe = toe_position(x, y, half, min_height=0.0)
    toe_cell = toe_position(x, y, half, min_height=dx)
    wall = height_at_wall(x, y, half)
    rms, max_abs = rms_height_difference(xc, height, *exp["surface"])

    xf_sim, yf_sim = failure_surface(x, y, moved, STATIC_THRESHOLD, edges, half_size=half)
    found = np.isfinite(yf_sim)
    if np.any(found):
        f_rms, f_max = rms_height_difference(xf_sim[found], yf_sim[found], *exp["failure"])
    else:   # everything moved (a frictionless floor): no failure surface
        f_rms = f_max = float("nan")
    xf_exp = exp["failure"][0]
    # fit over the stretch where the experiment defines the slip line, so that the flat top of
    # the static wedge near the wall does not enter the simulated fit
    in_range = found & (xf_sim >= xf_exp.min()) & (xf_sim <= xf_exp.max())
    angle = slip_angle(xf_sim[in_range], yf_sim[in_range])

    history = load_history(run_dir)
    kinetic = history.get("kinetic_energy", np.zeros(0))
    kinetic_ratio = (float(kinetic[-1] / kinetic.max())
                     if kinetic.size and kinetic.max() > 0 else None)
    mass0, mass1 = float(np.sum(first["mass"])), float(np.sum(last["mass"]))
    volume0, volume1 = float(np.sum(first["volume"])), float(np.sum(last["volume"]))
    metrics = {
        "time_s": last["time"],
        "toe_m": toe,
        "toe_one_cell_thick_m": toe_cell,
        "runout_ratio": (toe - COLUMN_WIDTH) / COLUMN_WIDTH,
        "height_at_wall_m": wall,
        "surface_rms_m": rms,
        "surface_max_abs_m": max_abs,
        "failure_rms_m": f_rms,
        "failure_max_abs_m": f_max,
        "slip_angle_deg": angle,
        "deposit_reaches_end_wall": bool(np.max(x + half) >= length - dx),
        "max_move_last_window_m": float(np.max(np.linalg.norm(
            last["position"] - before["position"], axis=1))),
        "rest_window_s": last["time"] - before["time"],
        "kinetic_final_over_peak": kinetic_ratio,
        "mass_relative_change": (mass1 - mass0) / mass0,
        "volume_relative_change": (volume1 - volume0) / volume0,
        "particles": int(x.size),
    }
    arrays = {"x": x, "y": y, "moved": moved, "half": half, "xc": xc, "height": height,
              "xf": xf_sim[found], "yf": yf_sim[found], "length": length}
    return metrics, arrays


def target(name, value, reference, band, passed, gating, why, unit="m"):
    """One compared figure (mpm_post.validation.target) in m, unless ``unit`` is mm or deg."""
    return _target(name, value, reference, band, passed, gating, why, unit=unit)


def compare(metrics, exp, dx, mode):
    """The targets of the issue (gating) and the other comparisons (reported).

    ``mode``: "full" (the case file, 5 mm cells: the issue's targets gate), "refined" (2.5 mm:
    the same comparisons, all reported, to show the convergence under refinement) or "coarse"
    (10 mm, make test: regression bands).
    """
    toe_error = (metrics["toe_m"] - exp["toe_m"]) / exp["toe_m"]
    metrics["toe_relative_error"] = toe_error
    cell = f"{dx * 1e3:g} mm"
    if mode == "coarse":
        toe_band, surface_band, wall_band = COARSE_TOE_BAND, 2.0 * dx, 2.0 * dx
        toe_why = ("regression band of make test, not the issue target (the same run is "
                   "held to 5 % by make validate): it must not fail on the round-off of a "
                   "change of the code, and it catches a change for the worse (pure FLIP "
                   "without separation ran 34 % too far), while the surface RMS and the wall "
                   "height hold the bulk of the deposit to two cells")
        surface_why = f"two {cell} cells: the surface of the particle cloud is known to a cell"
    else:
        toe_band, surface_band, wall_band = TOE_BAND, SURFACE_BAND, SURFACE_BAND
        toe_why = ("issue target: 5 % of the measured toe at a resolution that runs in a few "
                   "minutes on 2 cores (5 mm cells); a published explicit GIMP code ends 3.6 % "
                   "short" if mode == "full" else
                   "reported, the issue target applied to the refined run: the runout grows "
                   "under refinement, so the match of the 5 mm case is numerical dissipation "
                   "(see what the model misses)")
        surface_why = ("issue target: the free surface within a few millimetres RMS; the "
                       "digitised data are known to about a millimetre")
        if mode == "refined":
            surface_why = "reported: the issue's band applied to the refined run"
    gating = mode != "refined"
    results = [
        target("toe", metrics["toe_m"], exp["toe_m"], f"within {toe_band:.0%}",
               abs(toe_error) <= toe_band, gating, toe_why),
        target("free surface RMS", metrics["surface_rms_m"], None,
               f"<= {surface_band * 1e3:g} mm",
               metrics["surface_rms_m"] <= surface_band, gating, surface_why, unit="mm"),
        target("height at wall", metrics["height_at_wall_m"], exp["height_at_wall_m"],
               f"within {wall_band * 1e3:g} mm",
               abs(metrics["height_at_wall_m"] - exp["height_at_wall_m"]) <= wall_band, gating,
               "one cell of the case file (5 mm), as the surface RMS" if mode != "coarse" else
               f"two {cell} cells, as the surface RMS"),
        target("failure surface RMS", metrics["failure_rms_m"], None,
               f"<= {2.0 * dx * 1e3:g} mm", metrics["failure_rms_m"] <= 2.0 * dx, False,
               f"two {cell} cells; reported, not a target of the issue: the line depends on the "
               f"{STATIC_THRESHOLD * 1e3:g} mm threshold that separates static from moved",
               unit="mm"),
        target("slip angle", metrics["slip_angle_deg"], exp["slip_angle_deg"], "within 5 deg",
               abs(metrics["slip_angle_deg"] - exp["slip_angle_deg"]) <= 5.0, False,
               "reported: a straight fit through a curved line; the digitised points move the "
               "experimental angle by a few degrees depending on which are fitted", unit="deg"),
    ]
    return results, all(t["passed"] for t in results if t["gating"])


# ---------------------------------------------------------------------------------------------
# plots
# ---------------------------------------------------------------------------------------------

def _experiment_lines(axes, exp):
    axes.plot(*exp["surface"], color="red", lw=1.6, label="experiment: free surface")
    axes.plot(*exp["failure"], color="red", lw=1.4, ls="--",
              label="experiment: failure surface")
    axes.plot([0, COLUMN_WIDTH, COLUMN_WIDTH], [COLUMN_HEIGHT, COLUMN_HEIGHT, 0], color="0.4",
              lw=1.0, ls=":", label="initial column")


def plot_deposit(path, arrays, metrics, exp, title):
    figure = agg_figure(9.0, 2.9)
    axes = figure.add_subplot()
    cloud = axes.scatter(arrays["x"], arrays["y"], c=arrays["moved"] * 100.0, s=0.5, lw=0,
                         cmap="viridis", rasterized=True)
    figure.colorbar(cloud, ax=axes, label="displacement [cm]", shrink=0.6,
                    pad=0.01)
    axes.plot(arrays["xc"], arrays["height"], color="black", lw=1.0, label="model: free surface")
    axes.plot(arrays["xf"], arrays["yf"], color="orange", lw=1.2, ls="--",
              label=f"model: failure surface (|u| < {STATIC_THRESHOLD * 1e3:g} mm)")
    _experiment_lines(axes, exp)
    axes.axvline(metrics["toe_m"], color="black", lw=0.6, ls="-.")
    axes.text(metrics["toe_m"], 0.102, f"toe {metrics['toe_m']:.3f} m ", fontsize=7,
              ha="right")
    axes.set_xlim(0.0, max(0.5, min(arrays["length"], metrics["toe_m"] + 0.02)))
    axes.set_ylim(0.0, 0.11)
    axes.set_aspect("equal")
    axes.set_xlabel("x [m]")
    axes.set_ylabel("y [m]")
    axes.set_title(title, fontsize=9)
    figure.legend(*axes.get_legend_handles_labels(), fontsize=7, loc="outside lower center",
                  ncol=3, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def plot_sensitivity(path, surfaces, exp, study):
    figure = agg_figure(9.0, 2.7)
    axes = figure.add_subplot()
    colours = ("black", "tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown")
    for (key, (xc, height)), colour in zip(surfaces.items(), colours):
        axes.plot(xc, height, color=colour, lw=1.0,
                  label=f"model, floor {key}" if study == "floors" else f"model, {key}")
    _experiment_lines(axes, exp)
    right = max(float(xc[height > 0].max()) if np.any(height > 0) else 0.5
                for xc, height in surfaces.values())
    axes.set_xlim(0.0, max(0.5, right + 0.02))
    axes.set_ylim(0.0, 0.11)
    axes.set_aspect("equal")
    axes.set_xlabel("x [m]")
    axes.set_ylabel("y [m]")
    what = "three floor conditions" if study == "floors" else "variants of the numerics"
    axes.set_title(f"Bui et al. (2008), 5 mm cells: final free surface for {what}", fontsize=9)
    figure.legend(*axes.get_legend_handles_labels(), fontsize=7, loc="outside lower center",
                  ncol=4, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


# ---------------------------------------------------------------------------------------------
# modes
# ---------------------------------------------------------------------------------------------

def validate(args, case, mode):
    """Run (or read) one resolution and compare it; returns the exit code (the refined run
    reports only: 0 unless it fails to run)."""
    exp = experiment()
    tag = mode
    output = Path(args.output) if args.output else REPO / "outputs" / case["name"]
    wall = None
    if not args.no_run:
        wall = run_case(args.exe, case, output, overwrite=args.output is None, quiet=args.quiet)
    metrics, arrays = analyse(output, case, exp)
    results, passed = compare(metrics, exp, case["domain"]["dx"], mode)
    resolution = f"{case['domain']['dx'] * 1e3:g} mm cells"
    report = {
        "case": "bui2008",
        "title": "2D collapse of a column of aluminium bars (Bui et al. 2008)",
        "resolution": tag,
        "setup": setup_summary(case, metrics["particles"]),
        "experiment": {"toe_m": exp["toe_m"], "height_at_wall_m": exp["height_at_wall_m"],
                       "slip_angle_deg": exp["slip_angle_deg"],
                       "source": "data/README.md"},
        "metrics": metrics,
        "targets": results,
        "passed": passed,
        "wall_time_s": wall,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "mpm_geo": exe_version(args.exe) if not args.no_run else None,
        "output": relative(output),
        "static_threshold_m": STATIC_THRESHOLD,
        "what_the_model_misses": WHAT_THE_MODEL_MISSES,
    }
    results_dir = Path(args.results)
    suffix = "" if mode == "full" else f"_{mode}"
    png = results_dir / f"bui2008{suffix}.png"
    report["plots"] = [png.name]
    plot_deposit(png, arrays, metrics, exp,
                 f"Bui et al. (2008) column collapse, {resolution}, t = {metrics['time_s']:.2f} s:"
                 f" particles coloured by displacement")
    write_json(results_dir / f"metrics{suffix}.json", report)
    print_table(results, (22, 10, 11, 16), reference="experiment")
    print(f"toe of the deposit at least one cell thick: {metrics['toe_one_cell_thick_m']:.4f} m;"
          f" volume change {metrics['volume_relative_change']:+.1%}; kinetic energy at the end"
          f" / peak {metrics['kinetic_final_over_peak']}")
    print(f"wrote {results_dir / f'metrics{suffix}.json'} and {png}")
    print(f"bui2008 ({tag}): {'PASS' if passed else 'FAIL (a target is missed)'}"
          + (" (reported only)" if mode == "refined" else ""))
    return 0 if passed else 1


def ladder_rungs(case):
    """The case at each cell size of LADDER_DX (the case file itself at its own)."""
    return [case if abs(dx - case["domain"]["dx"]) < 1e-12 else
            coarse_case(case, dx, f"ladder_{dx * 1e3:g}mm".replace(".", "p")) for dx in LADDER_DX]


def ladder_targets(rows, exp):
    """The targets of the refinement ladder (all reported), from ``rows`` (coarse to fine, each
    with ``dx_m``, ``toe_m``, ``toe_thick_m``, ``surface_rms_m``). Returns (targets, fits).

    Bands derived, not picked: the uncertainty of the measurement (TOE_UNCERTAINTY,
    SURFACE_UNCERTAINTY) plus Roache's factor of safety times each rung's discretisation error
    estimated from the ladder itself (mpm_post.study.richardson: 1.25 with an observed order,
    3 without one); the extrapolated value within the uncertainty plus the GCI of the finest
    rung; the ladder must converge (successive differences of one sign, the finer smaller).
    And the goal of issue 19 at every rung: the toe within 5 %, the free-surface RMS below 3 mm.
    """
    measures = [
        ("toe", "toe_m", exp["toe_m"], TOE_UNCERTAINTY),
        (f"toe of the deposit thicker than {LADDER_THICKNESS * 1e3:g} mm", "toe_thick_m",
         measured_toe_at(exp, LADDER_THICKNESS), TOE_UNCERTAINTY),
    ]
    out, fits = [], {}
    for label, key, reference, uncertainty in measures:
        values = [r[key] for r in rows]
        fit = richardson(values, ratio=rows[-2]["dx_m"] / rows[-1]["dx_m"])
        fits[key] = fit
        for r, err in zip(rows, fit.errors):
            band = uncertainty + fit.safety * err
            out.append(target(
                f"{label}, {r['dx_m'] * 1e3:g} mm", r[key], reference, f"+- {band * 1e3:.1f} mm",
                abs(r[key] - reference) <= band, False,
                f"the measurement's {uncertainty * 1e3:g} mm + {fit.safety:g} x the rung's "
                f"estimated discretisation error {err * 1e3:.1f} mm"))
        d = [values[i + 1] - values[i] for i in range(len(values) - 1)]
        ratio = abs(d[-1]) / abs(d[-2]) if d[-2] != 0.0 else math.inf
        out.append(target(
            f"{label}: ladder converges", ratio, None, "< 1, one sign",
            fit.monotone, False,
            "successive differences " + ", ".join(f"{x * 1e3:+.1f} mm" for x in d)
            + "; without convergence no discretisation error can be estimated"))
        out.append(target(
            f"{label}: extrapolated", fit.extrapolated, reference,
            f"+- {(uncertainty + fit.gci_fine) * 1e3:.1f} mm",
            abs(fit.extrapolated - reference) <= uncertainty + fit.gci_fine, False,
            (f"observed order {fit.order:.2f}" if math.isfinite(fit.order) else
             "no order observed: the finest value, its error the last difference")
            + f"; band: the measurement's {uncertainty * 1e3:g} mm + the GCI of the finest "
              f"rung {fit.gci_fine * 1e3:.1f} mm"))
    for r in rows:
        cell = f"{r['dx_m'] * 1e3:g} mm"
        error = (r["toe_m"] - exp["toe_m"]) / exp["toe_m"]
        out.append(target(f"goal: toe within {TOE_BAND:.0%}, {cell}", r["toe_m"], exp["toe_m"],
                          f"within {TOE_BAND:.0%}", abs(error) <= TOE_BAND, False,
                          "goal of issue 19 at every rung, one set of settings"))
        out.append(target(f"goal: free surface RMS, {cell}", r["surface_rms_m"], None,
                          f"<= {GOAL_SURFACE * 1e3:g} mm", r["surface_rms_m"] <= GOAL_SURFACE,
                          False, "goal of issue 19 at every rung", unit="mm"))
    return out, fits


def ladder(args, case):
    """Run (or read) the ladder, compare it and write results/metrics_ladder.json; reported
    only (exit 0 unless a run fails: the goal is not met, docs/study/runout_refinement.md)."""
    exp = experiment()
    base = Path(args.output) if args.output else REPO / "outputs"
    rows, walls, clouds = [], [], []
    for rung in ladder_rungs(case):
        output = base / rung["name"]
        wall = None
        if not args.no_run:
            wall = run_case(args.exe, rung, output, overwrite=args.output is None,
                            quiet=args.quiet)
        metrics, arrays = analyse(output, rung, exp)
        metrics["toe_thick_m"] = toe_position(arrays["x"], arrays["y"], arrays["half"],
                                              min_height=LADDER_THICKNESS)
        metrics["dx_m"] = rung["domain"]["dx"]
        rows.append(metrics)
        walls.append(wall)
        clouds.append(arrays)
    targets, fits = ladder_targets(rows, exp)
    toe = ", ".join(f"{r['toe_m']:.4f} m ({(r['toe_m'] / exp['toe_m'] - 1) * 100:+.1f} %)"
                    for r in rows)
    thick_ref = measured_toe_at(exp, LADDER_THICKNESS)
    thick = ", ".join(f"{(r['toe_thick_m'] / thick_ref - 1) * 100:+.1f} %" for r in rows)
    rms = ", ".join(f"{r['surface_rms_m'] * 1e3:.1f}" for r in rows)
    cells = " / ".join(f"{dx * 1e3:g}" for dx in LADDER_DX)
    goal = all(t["passed"] for t in targets if t["name"].startswith("goal"))
    headline = (
        f"Toe against the measured {exp['toe_m']:.4f} m at {cells} mm cells: {toe}"
        + ("; the ladder converges" if fits["toe_m"].monotone else
           "; the ladder does not converge") + f". The deposit thicker than "
        f"{LADDER_THICKNESS * 1e3:g} mm against the measured front at that thickness "
        f"({thick_ref:.4f} m): {thick}. Free-surface RMS {rms} mm. Goal of issue 19 (toe within "
        f"5 %, RMS below 3 mm at every rung) {'met' if goal else 'not met'}.")
    table = {"title": "Per cell size",
             "header": ["cells", "particles", "toe", "toe - measured",
                        f"toe, thicker than {LADDER_THICKNESS * 1e3:g} mm", "surface RMS",
                        "height at wall", "volume change", "mpm_geo wall time"],
             "rows": [[f"{r['dx_m'] * 1e3:g} mm", r["particles"], f"{r['toe_m']:.4f} m",
                       f"{(r['toe_m'] / exp['toe_m'] - 1) * 100:+.1f} %",
                       f"{r['toe_thick_m']:.4f} m", f"{r['surface_rms_m'] * 1e3:.1f} mm",
                       f"{r['height_at_wall_m']:.4f} m", f"{r['volume_relative_change']:+.1%}",
                       "-" if w is None else f"{w:.0f} s"] for r, w in zip(rows, walls)]}
    report = {
        "case": "bui2008",
        "title": "2D collapse of a column of aluminium bars (Bui et al. 2008)",
        "resolution": "ladder",
        "heading": f"refinement ladder, {cells} mm cells (reported: the goal of issue 19)",
        "headline": headline,
        "reported": True,
        "setup": setup_summary(ladder_rungs(case)[0], rows[0]["particles"]),
        "experiment": {"toe_m": exp["toe_m"], "height_at_wall_m": exp["height_at_wall_m"],
                       "slip_angle_deg": exp["slip_angle_deg"],
                       "toe_thick_m": thick_ref, "source": "data/README.md"},
        "metrics": {"resolutions": rows,
                    "fits": {k: f._asdict() for k, f in fits.items()}},
        "targets": targets,
        "tables": [table],
        "passed": all(t["passed"] for t in targets),
        "wall_time_s": sum(walls) if None not in walls else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "notes": ["The set-up rows are those of the coarsest rung; the finer ones change only "
                  "the cell size (and so the particle count).",
                  "Why the toe grows and what was tried: docs/study/runout_refinement.md."],
    }
    results_dir = Path(args.results)
    png = results_dir / "bui2008_ladder.png"
    plot_ladder(png, rows, clouds, exp)
    report["plots"] = [png.name]
    write_json(results_dir / "metrics_ladder.json", report)
    print_table(targets, (22, 10, 11, 16), reference="experiment")
    print(headline)
    print(f"wrote {results_dir / 'metrics_ladder.json'} and {png}")
    print(f"bui2008 (ladder): {'PASS' if report['passed'] else 'goal not met'} (reported only)")
    return 0 if report["passed"] else 1


def plot_ladder(path, rows, clouds, exp):
    """The final free surfaces of the rungs against the measured one."""
    figure = agg_figure(9.0, 2.9)
    axes = figure.add_subplot()
    for r, arrays, colour in zip(rows, clouds, ("tab:blue", "tab:orange", "tab:green")):
        axes.plot(arrays["xc"], arrays["height"], color=colour, lw=1.0,
                  label=f"{r['dx_m'] * 1e3:g} mm cells, toe {r['toe_m']:.3f} m")
    _experiment_lines(axes, exp)
    axes.axhline(LADDER_THICKNESS, color="0.5", lw=0.6, ls=":",
                 label=f"{LADDER_THICKNESS * 1e3:g} mm")
    axes.set_xlim(0.0, max(0.5, max(r["toe_m"] for r in rows) + 0.02))
    axes.set_ylim(0.0, 0.11)
    axes.set_aspect("equal")
    axes.set_xlabel("x [m]")
    axes.set_ylabel("y [m]")
    axes.set_title("Bui et al. (2008): final free surface under refinement", fontsize=9)
    figure.legend(*axes.get_legend_handles_labels(), fontsize=7, loc="outside lower center",
                  ncol=3, frameon=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def variants(study, case):
    """(key, label, case) of each run of a sensitivity study ("floors" or "numerics")."""
    out = []
    if study == "floors":
        for floor in FLOORS:
            variant = with_floor(case, floor)
            out.append((floor, describe_floor(variant), variant))
    else:
        for key, (label, change) in NUMERICS.items():
            variant = copy.deepcopy(case)
            if change is not None:
                change(variant)
            variant["name"] = f"{case['name']}_{key}"
            out.append((key, label, variant))
    return out


SENSITIVITY_NOTES = {
    "floors": "runs of the case file that differ only in the floor; top face closed (sliding) "
              "in these runs so that material splashing up the end wall stays in the grid",
    "numerics": "runs that differ from the case file in one numerical choice each",
}


def sensitivity(args, case, study):
    """Runs of one sensitivity study at the case's resolution; informational, exit 0 unless a
    run fails."""
    exp = experiment()
    base = Path(args.output) if args.output else REPO / "outputs"
    rows, surfaces = {}, {}
    for key, label, variant in variants(study, case):
        output = base / variant["name"]
        wall = None
        if not args.no_run:
            wall = run_case(args.exe, variant, output, overwrite=args.output is None,
                            quiet=True)
        metrics, arrays = analyse(output, variant, exp)
        results, _ = compare(metrics, exp, variant["domain"]["dx"], "full")
        rows[key] = {"label": label, "metrics": metrics, "targets": results,
                     "wall_time_s": wall}
        surfaces[key] = (arrays["xc"], arrays["height"])
        print(f"{key:<14} toe {metrics['toe_m']:.4f} m  wall "
              f"{metrics['height_at_wall_m']:.4f} m  RMS {metrics['surface_rms_m'] * 1e3:.1f} mm"
              f"  failure RMS {metrics['failure_rms_m'] * 1e3:.1f} mm"
              f"  angle {metrics['slip_angle_deg']:.1f} deg"
              f"  volume {metrics['volume_relative_change']:+.1%}"
              + ("  (reaches the end wall)" if metrics["deposit_reaches_end_wall"] else ""))
    results_dir = Path(args.results)
    png = results_dir / f"bui2008_{study}.png"
    plot_sensitivity(png, surfaces, exp, study)
    path = results_dir / f"sensitivity_{study}.json"
    write_json(path, {
        "case": "bui2008", "study": study, "resolution": "full",
        "dx_m": case["domain"]["dx"], "note": SENSITIVITY_NOTES[study],
        "rows": rows, "plots": [png.name]})
    print(f"wrote {path} and {png}")
    return 0


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--coarse", action="store_true",
                      help=f"run a copy with {COARSE_DX * 1e3:g} mm cells (toe regression "
                           f"band {COARSE_TOE_BAND * 100:.0f} %%)")
    mode.add_argument("--refined", action="store_true",
                      help=f"run a copy with {REFINED_DX * 1e3:g} mm cells (convergence under "
                           "refinement; reported, exit 0 unless the run fails)")
    mode.add_argument("--ladder", action="store_true",
                      help="run the case at " + ", ".join(f"{dx * 1e3:g}" for dx in LADDER_DX)
                           + " mm cells: the refinement ladder with derived bands, reported "
                             "(exit 1 when a band or the goal is missed)")
    mode.add_argument("--floors", action="store_true",
                      help="runs with floor mu = tan(phi), fixed and frictionless")
    mode.add_argument("--numerics", action="store_true",
                      help="runs that change one numerical choice of the case each")
    common_arguments(parser, RESULTS,
                     output_help="output folder (default: outputs/bui2008[_coarse|_refined], "
                                 "overwritten); a folder given here must not exist (--floors, "
                                 "--numerics: parent folder)",
                     no_run_help="analyse the existing output instead of running")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if not args.no_run and exe_missing(args.exe):
        return 2
    case = load_case(CASE)
    try:
        if args.floors or args.numerics:
            return sensitivity(args, case, "floors" if args.floors else "numerics")
        if args.coarse:
            return validate(args, coarse_case(case), "coarse")
        if args.refined:
            return validate(args, coarse_case(case, REFINED_DX, "refined"), "refined")
        if args.ladder:
            return ladder(args, case)
        return validate(args, case, "full")
    except (OSError, ValueError, RuntimeError, KeyError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
