#!/usr/bin/env python3
"""Verification: a uniform strip load on an elastic ground against Flamant's stresses.

A strip of half-width a = 1 m loaded by q = 10 kPa (a traction of `loads`, ramped up over
0.5 s, damped to rest by 2.5 s with local damping 0.6) on a weightless linear elastic ground (E = 10 MPa, nu = 0.3),
the half model (x = 0 a symmetry plane), in a square box of side L = 16 a (sliding side walls,
fixed base), at a / dx = 4, 8 and 16; and the same at a / dx = 8 in a box of side 8 a, to
measure what the finite box changes. Closed form for the half-space (Flamant, Boussinesq;
Poulos and Davis 1974, Elastic Solutions for Soil and Rock Mechanics, 3.1), compression
positive, theta_1, theta_2 the angles from the vertical to the strip's edges seen from the
point, alpha = theta_2 - theta_1:

    s_z = q / pi (alpha + sin(alpha) cos(theta_1 + theta_2)),
    s_x = q / pi (alpha - sin(alpha) cos(theta_1 + theta_2)).

Compared at every particle (at its initial position) of the near field |x| <= 2 a,
a / 2 <= z <= 4 a: the L1 error sum |s - s_exact| V / (q sum V) of s_z and of s_x.

Expected errors (why the bands are what they are):
- the particle stress of cpGIMP at rest is that of linear elements sampled off their centres:
  first order in dx (validation/column_self_weight: 1 / (4 N)), so the s_z error should halve
  from a / dx = 4 to 8 to 16 (an observed order near 1);
- the box is not a half-space: its fixed base carries part of the load's spread. Its effect on
  s_z is measured by the 8 a box against the 16 a box at the same dx (0.6 % of q on the mean
  s_z, the base effect falling as (a / L)^2, so about 0.15 % at 16 a). Band on the finest
  s_z error: 1 % of q, twice the first-order extrapolation (0.2 %) plus the box (0.15 %).
- s_x is not gated: in the box it is lower than Flamant's by a nearly uniform 3 % of q under
  the whole near field, which falls only slowly with the box (4.0 % at 8 a, 3.1 % at 16 a):
  the box's side walls and base hold the ground laterally where a half-space does not. It is
  reported, not hidden.

    .venv/bin/python validation/strip_load/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/strip_load.png.
Exit codes: 0 every target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import math
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post import list_outputs, load_history, load_particles  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, load_json, relative, target, verdict, write_json)

RESULTS = HERE / "results"
LADDER = ["strip_load_a4", "strip_load_a8", "strip_load_a16"]
BOX8 = "strip_load_a8_box8"
FINEST_BAND = 0.01      # L1 error of s_z at a / dx = 16, fraction of q
ORDER_MIN = 0.7         # observed order of the s_z error over the ladder (first order: 1)
REST = 1e-4             # kinetic energy at the end / elastic energy: at rest
SX_BAND = 0.01          # s_x: what a half-space comparison would ask (reported only)


def flamant(x, z, q, a):
    """Flamant's stresses (s_z, s_x), compression positive, under a strip |x| <= a."""
    t1 = np.arctan2(x - a, z)
    t2 = np.arctan2(x + a, z)
    alpha = t2 - t1
    mixed = np.sin(alpha) * np.cos(t1 + t2)
    return q / math.pi * (alpha + mixed), q / math.pi * (alpha - mixed)


def parameters(case):
    load = case["loads"][0]
    size = case["bodies"][0]["max"][1]
    return {"q": load["pressure"], "a": load["max"][0], "size": size,
            "dx": case["domain"]["dx"], "top": size}


def analyse(run_dir, par):
    """Errors of the last output of one run in the near field."""
    outputs = list_outputs(run_dir)
    if not outputs:
        raise FileNotFoundError(f"no particle output in {run_dir}")
    last = load_particles(outputs[-1][1])
    x0 = last["position"] - last["displacement"]
    z = par["top"] - x0[:, 1]
    x = x0[:, 0]
    q, a = par["q"], par["a"]
    near = (x <= 2 * a) & (z >= 0.5 * a) & (z <= 4 * a)
    sz_exact, sx_exact = flamant(x[near], z[near], q, a)
    sz = -last["stress"][near, 1]
    sx = -last["stress"][near, 0]
    volume = last["volume"][near]
    history = load_history(run_dir)
    elastic = history["elastic_energy"][-1]
    centre = (x < 0.5 * par["dx"]) & (np.abs(z - a) <= 0.5 * par["dx"])
    sz_c_exact, _ = flamant(x[centre], z[centre], q, a)
    return {
        "a_over_dx": a / par["dx"],
        "box_over_a": par["size"] / a,
        "particles_near_field": int(near.sum()),
        "time_s": last["time"],
        "sz_l1": float(np.sum(np.abs(sz - sz_exact) * volume) / (q * volume.sum())),
        "sz_mean": float(np.sum((sz - sz_exact) * volume) / (q * volume.sum())),
        "sx_l1": float(np.sum(np.abs(sx - sx_exact) * volume) / (q * volume.sum())),
        "sx_mean": float(np.sum((sx - sx_exact) * volume) / (q * volume.sum())),
        "sz_centre_ratio": float(np.mean(-last["stress"][centre, 1] / sz_c_exact)),
        "kinetic_over_elastic": float(history["kinetic_energy"][-1] / elastic),
        "energy_residual_over_load_work": float(history["residual"][-1]
                                                / history["load_work"][-1]),
    }, {"x": x, "z": z, "sz": -last["stress"][:, 1], "sx": -last["stress"][:, 0]}


def observed_order(rows):
    ratio = np.array([r["a_over_dx"] for r in rows])
    errors = np.array([r["sz_l1"] for r in rows])
    return float(np.polyfit(np.log(ratio), -np.log(errors), 1)[0])


def targets_of(rows, box8):
    finest = rows[-1]
    order = observed_order(rows)
    same_dx = rows[1]
    out = [
        target(f"s_z L1 error, a / dx = {finest['a_over_dx']:g}", finest["sz_l1"], 0.0,
               f"<= {FINEST_BAND:.0%} of q", finest["sz_l1"] <= FINEST_BAND, True,
               "first order in dx (0.8 % at a / dx = 4 extrapolates to 0.2 % at 16) plus the "
               "finite box's base (0.15 % at 16 a, from the 8 a box); band twice that",
               unit="rel"),
        target("observed order of the s_z error", order, 1.0, f">= {ORDER_MIN}",
               order >= ORDER_MIN, True,
               "the particle stress of linear elements sampled off their centres is first "
               "order in dx"),
        target(f"s_z under the centre at z = a, a / dx = {finest['a_over_dx']:g}",
               finest["sz_centre_ratio"] - 1.0, 0.0, "+-2 %",
               abs(finest["sz_centre_ratio"] - 1.0) <= 0.02, True,
               "the L1 band at one point: the particles at depth a under the centre",
               unit="rel"),
        target("at rest: kinetic / elastic energy at the end", finest["kinetic_over_elastic"],
               None, f"<= {REST:g}", finest["kinetic_over_elastic"] <= REST, True,
               "the static solution is compared: the damped ground must have come to rest"),
        target("energy residual / load work", finest["energy_residual_over_load_work"], 0.0,
               "+-1 %", abs(finest["energy_residual_over_load_work"]) <= 0.01, True,
               "the load's work is booked (load_work): the balance closes", unit="rel"),
        target("box effect on the mean s_z (8 a box - 16 a box, a / dx = 8)",
               box8["sz_mean"] - same_dx["sz_mean"], None, "reported", True, False,
               "what the fixed base of a smaller box adds; it falls as (a / L)^2",
               unit="rel"),
        target(f"s_x L1 error, a / dx = {finest['a_over_dx']:g}", finest["sx_l1"], 0.0,
               f"<= {SX_BAND:.0%} of q (half-space)", finest["sx_l1"] <= SX_BAND, False,
               f"s_x lies a nearly uniform {-finest['sx_mean']:.1%} of q below Flamant's over "
               f"the near field (8 a box: {-box8['sx_mean']:.1%}): the box's walls and base "
               "hold the ground laterally; not a half-space", unit="rel"),
    ]
    return out


def plot(path, arrays, rows, par):
    figure = agg_figure(10, 4)
    left, middle, right = figure.subplots(1, 3)
    a = par["a"]
    z_line = np.linspace(0.05, 6, 200)
    sz_line, sx_line = flamant(np.zeros_like(z_line), z_line, par["q"], a)
    for name, style in zip(LADDER, ("o", "s", ".")):
        arr = arrays[name]
        column = (arr["x"] < 0.5 * par["dx_of"][name]) & (arr["z"] < 6)
        left.plot(arr["sz"][column] / par["q"], arr["z"][column], style, ms=3,
                  label=f"MPM a/dx = {a / par['dx_of'][name]:g}")
        middle.plot(arr["sx"][column] / par["q"], arr["z"][column], style, ms=3)
    left.plot(sz_line / par["q"], z_line, "k-", lw=1, label="Flamant")
    middle.plot(sx_line / par["q"], z_line, "k-", lw=1)
    for axes, title in ((left, "s_z / q under the centre"), (middle, "s_x / q under the centre")):
        axes.invert_yaxis()
        axes.set_ylabel("depth z [m]")
        axes.set_title(title, fontsize=9)
    left.legend(fontsize=7)
    ratio = [r["a_over_dx"] for r in rows]
    right.loglog(ratio, [r["sz_l1"] for r in rows], "o-", label="s_z L1")
    right.loglog(ratio, [r["sx_l1"] for r in rows], "s-", label="s_x L1")
    right.loglog(ratio, [rows[0]["sz_l1"] * ratio[0] / r for r in ratio], "k:", label="order 1")
    right.set_xlabel("a / dx")
    right.set_ylabel("L1 error / q, near field")
    right.legend(fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent folder of the runs (default: outputs/, the runs "
                                 "overwritten); folders under a parent given here must not exist",
                     no_run_help="analyse the existing outputs")
    args = parser.parse_args(argv)
    parent = Path(args.output) if args.output else REPO / "outputs"
    rows, arrays, par_of, wall = [], {}, {}, 0.0
    try:
        for name in LADDER + [BOX8]:
            case_path = HERE / f"{name}.json"
            case = load_json(case_path)
            output = parent / case["name"]
            if not args.no_run:
                if exe_missing(args.exe):
                    return 2
                wall += run_mpm_geo(args.exe, case_path, output, overwrite=args.output is None,
                                    quiet=args.quiet)
            par = parameters(case)
            par_of[name] = par
            metrics, arr = analyse(output, par)
            arrays[name] = arr
            if name in LADDER:
                rows.append(metrics)
            else:
                box8 = metrics
    except (OSError, ValueError, RuntimeError, KeyError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    results = targets_of(rows, box8)
    passed = all(t["passed"] for t in results if t["gating"])
    par = dict(par_of[LADDER[-1]])
    par["dx_of"] = {name: p["dx"] for name, p in par_of.items()}
    finest = rows[-1]
    report = {
        "case": "strip_load",
        "title": "A uniform strip load on an elastic ground against Flamant's stresses "
                 "(traction of `loads`, half model)",
        "resolution": "full",
        "heading": "a / dx = 4, 8, 16 (250, 125, 62.5 mm cells)",
        "case_files": [relative(HERE / f"{n}.json") for n in LADDER + [BOX8]],
        "headline": f"Under the strip, s_z agrees with Flamant's to {finest['sz_l1']:.2%} of q "
                    f"(L1 over |x| <= 2a, a/2 <= z <= 4a, a / dx = 16), converging at order "
                    f"{observed_order(rows):.2f}; s_x lies {-finest['sx_mean']:.1%} of q below "
                    "it, the lateral hold of the finite box (reported).",
        "setup": {"rows": [
            ["strip", f"half-width a = {par['a']:g} m, q = {par['q']:g} Pa, ramp 0.5 s"],
            ["ground", "linear elastic, E = 10 MPa, nu = 0.3, weightless, local damping 0.6"],
            ["box", "16 a x 16 a (and 8 a x 8 a at a / dx = 8); sliding sides, fixed base"],
            ["resolutions", "a / dx = 4, 8, 16; 2 x 2 particles per cell, cpGIMP, MUSL"],
        ]},
        "metrics": {"ladder": rows, "box8": box8},
        "targets": results,
        "passed": passed,
        "wall_time_s": None if args.no_run else wall,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
    }
    png = Path(args.results) / "strip_load.png"
    report["plots"] = [png.name]
    plot(png, arrays, rows, par)
    write_json(Path(args.results) / "metrics.json", report)
    for t in results:
        print(f"{t['name']:<56} {t['value']!s:<24} {t['band']:<30} {verdict(t)}")
    print(f"wrote {Path(args.results) / 'metrics.json'} and {png}")
    print(f"strip_load: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
