#!/usr/bin/env python3
"""Validation: the geostatic (K0) initial stress of a layered column, and that it is at rest.

A column 1 m wide and 10 m high between sliding walls on a fixed base (dx = 0.25 m, 2 x 2
particles per cell): sand from 0 to 5 m (Mohr-Coulomb, rho = 2000 kg/m3, phi = 30 deg, so
K0 = 1 - sin 30 = 0.5 after Jaky), clay from 5 to 10 m (linear elastic, rho = 1800 kg/m3,
nu = 0.3, K0 = nu / (1 - nu) = 0.4286), the clay given as a polygon; `initial_stress.type =
"k0"`, then 1 s of undamped motion under gravity. Closed form (../shared/REFERENCES.md section
9): sigma_v = -rho_c g (10 - y) in the clay, -rho_c g 5 - rho_s g (5 - y) in the sand,
sigma_h = K0 sigma_v, no shear.

Compared at every particle, at its initial height, at the end of the run: sigma_v and sigma_h
against the closed form, relative to rho_s g dx (the size of a discretisation error of the
stress; round-off is 1e-13 of it); the largest kinetic energy of the run against the elastic
energy the column starts with; the largest displacement; the base's vertical reaction
(history.csv) against the column's weight. Bands: 1e-9 for the stresses and the
energy ratio (round-off, not discretisation: with regular particles the K0 state is the
discrete equilibrium of the column), 1e-9 m for the displacement.

    .venv/bin/python validation/k0_column/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/k0_column.png.
Exit codes: 0 every target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post import load_history, load_particles  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, load_json, relative, target, verdict, write_json)

RESULTS = HERE / "results"
CASE = HERE / "k0_column.json"
BAND = 1.0e-9
G = 9.81


def closed_form(y, case):
    """(sigma_v, K0) at initial heights y: the weight above, the K0 of each layer."""
    sand, clay = case["materials"]
    top, interface = 10.0, 5.0
    sigma_v = np.where(y > interface, -clay["rho"] * G * (top - y),
                       -clay["rho"] * G * (top - interface) - sand["rho"] * G * (interface - y))
    k0_sand = 1.0 - np.sin(np.radians(sand["phi"]))
    k0_clay = clay["nu"] / (1.0 - clay["nu"])
    return sigma_v, np.where(y > interface, k0_clay, k0_sand)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="output folder (default: outputs/k0_column, overwritten); a "
                                 "folder given here must not exist",
                     no_run_help="analyse the existing output")
    args = parser.parse_args(argv)
    case = load_json(CASE)
    output = Path(args.output) if args.output else REPO / "outputs" / case["name"]
    wall = None
    try:
        if not args.no_run:
            if exe_missing(args.exe):
                return 2
            wall = run_mpm_geo(args.exe, CASE, output, overwrite=args.output is None,
                               quiet=args.quiet)
        end = load_particles(output)
        history = load_history(output)
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    dx = case["domain"]["dx"]
    scale = case["materials"][0]["rho"] * G * dx
    y0 = end["position"][:, 1] - end["displacement"][:, 1]
    sigma_v, k0 = closed_form(y0, case)
    stress = end["stress"]
    error_v = float(np.max(np.abs(stress[:, 1] - sigma_v)) / scale)
    error_h = float(np.max(np.abs(stress[:, 0] - k0 * sigma_v)) / scale)
    error_z = float(np.max(np.abs(stress[:, 2] - k0 * sigma_v)) / scale)
    shear = float(np.max(np.abs(stress[:, 3])) / scale)
    kinetic = float(np.max(history["kinetic_energy"]) / history["elastic_energy"][0])
    moved = float(np.max(np.abs(end["displacement"])))
    sand, clay = case["materials"]
    weight = G * (sand["rho"] * 5.0 + clay["rho"] * 5.0) * 1.0      # per metre, 1 m wide
    base = float(history["reaction_ymin_y"][-1])
    metrics = {
        "time_s": end["time"],
        "sigma_v_error_over_rho_g_dx": error_v,
        "sigma_h_error_over_rho_g_dx": error_h,
        "sigma_z_error_over_rho_g_dx": error_z,
        "shear_over_rho_g_dx": shear,
        "kinetic_peak_over_elastic": kinetic,
        "largest_displacement_m": moved,
        "base_reaction_over_weight": base / weight,
        "k0_sand": 0.5, "k0_clay": 0.3 / 0.7,
    }
    results = [
        target("sigma_v at 1 s: max error / (rho g dx)", error_v, 0.0, f"< {BAND:g}",
               error_v < BAND, True, "the weight above each particle, layer by layer"),
        target("sigma_h at 1 s: max error / (rho g dx)", error_h, 0.0, f"< {BAND:g}",
               error_h < BAND, True, "K0 of each layer (Jaky for the sand, nu / (1 - nu) for "
               "the clay) times sigma_v"),
        target("sigma_zz at 1 s: max error / (rho g dx)", error_z, 0.0, f"< {BAND:g}",
               error_z < BAND, True, "plane strain: the out-of-plane stress is K0 sigma_v too"),
        target("largest kinetic energy / elastic energy", kinetic, 0.0, f"< {BAND:g}",
               kinetic < BAND, True, "the column starts in equilibrium: nothing moves "
               "(undamped)"),
        target("largest displacement [m]", moved, 0.0, "< 1e-9", moved < 1e-9, True,
               "no settlement at all"),
        target("base reaction / weight - 1", base / weight - 1.0, 0.0, f"< {BAND:g}",
               abs(base / weight - 1.0) < BAND, True,
               "history.csv's reaction_ymin_y carries the column's weight"),
    ]
    passed = all(t["passed"] for t in results if t["gating"])

    figure = agg_figure(6.5, 5.0)
    axes = figure.add_subplot()
    order = np.argsort(y0)
    axes.plot(sigma_v[order] / 1e3, y0[order], color="black", lw=1.0, label="closed form sigma_v")
    axes.plot((k0 * sigma_v)[order] / 1e3, y0[order], color="black", lw=1.0, ls="--",
              label="closed form K0 sigma_v")
    axes.plot(stress[:, 1] / 1e3, y0, "o", ms=2.5, mfc="none", color="tab:blue",
              label="mpm-geo sigma_yy at 1 s")
    axes.plot(stress[:, 0] / 1e3, y0, "s", ms=2.5, mfc="none", color="tab:red",
              label="mpm-geo sigma_xx at 1 s")
    axes.axhline(5.0, color="0.6", lw=0.8)
    axes.text(0.02, 5.1, "clay above, sand below", ha="left", transform=axes.get_yaxis_transform(),
              fontsize=8)
    axes.set_xlabel("stress [kPa] (compression negative)")
    axes.set_ylabel("height y [m]")
    axes.set_title("K0 initial stress of a layered column", fontsize=10)
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8, loc="lower right")
    png = Path(args.results) / "k0_column.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(png, dpi=110)

    report = {
        "case": "k0_column",
        "title": "Geostatic (K0) initial stress of a layered column (initial_stress)",
        "resolution": "full",
        "heading": "H / dx = 40 (0.25 m cells)",
        "case_files": [relative(CASE)],
        "headline": f"After 1 s undamped, the stresses equal the closed form to "
                    f"{max(error_v, error_h, error_z):.1e} of rho g dx; the largest kinetic "
                    f"energy is {kinetic:.1e} of the elastic energy and nothing moves "
                    f"({moved:.1e} m); the base carries the weight to {abs(base / weight - 1):.0e}.",
        "setup": {"rows": [
            ["column", "1 m x 10 m, sliding walls, fixed base; gravity 9.81 m/s2"],
            ["sand", "0 to 5 m: mohr_coulomb rho 2000, E 50 MPa, nu 0.3, phi 30, c 0: K0 = 0.5"],
            ["clay", "5 to 10 m (a polygon): linear_elastic rho 1800, E 20 MPa, nu 0.3: "
                     "K0 = 0.4286"],
            ["grid", "dx = 0.25 m, 2 x 2 particles per cell, cpGIMP, MUSL, no damping, 1 s"],
        ]},
        "metrics": metrics,
        "targets": results,
        "passed": passed,
        "wall_time_s": wall,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
    }
    write_json(Path(args.results) / "metrics.json", report)
    for t in results:
        print(f"{t['name']:<42} {t['value']!s:<24} {t['band']:<10} {verdict(t)}")
    print(report["headline"])
    print(f"k0_column: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
