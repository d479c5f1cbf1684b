#!/usr/bin/env python3
"""Validation: Terzaghi's 1D consolidation of a saturated elastic column (pore water).

A column 1 m high, one cell wide between sliding walls, on a sliding impermeable base,
drained at its top (pore_water.faces.ymax = "drained"), linear elastic skeleton E = 1 GPa,
nu = 0 (M = 1 GPa), saturated density 2000 kg/m3, porosity 0.3, pore water K_w = 2 GPa (the
undrained pressure is p0 = q (1/M) / (1/M + n/K_w) = 0.870 q), and the hydraulic
conductivity k = c_v gamma_w (1/M + n/K_w) = 1.1278e-5 m/s of c_v = 1 m2/s: T_v = t / 1 s.
The stiff skeleton keeps the column's own dynamics fast against the consolidation (a drained
P-wave transit of 0.006 s, 0.6 % of H^2 / c_v), as in a real clay layer, where it is far
faster still. The top carries q = 10 kPa (a traction on the top particles) ramped over
0.00204 s, the transit time 4 H / c_u of the undrained column (c_u = 1958 m/s): a ramp of
one period of the first mode leaves no vibration of any mode of the column (its periods are
T_1 / (2n - 1)). No gravity, no damping. Three resolutions: 20, 40 and 80 cells (2 x 2
particles per cell, cpGIMP, MUSL), each run to T_v = 1.

Closed form: Terzaghi's series for that ramp (superposed step loads),
p(z, t) = sum_m 2 p0 / M_m sin(M_m z / H) f_m(T_v), M_m = (2m + 1) pi / 2,
f_m = (1 - exp(-M_m^2 T_v)) / (M_m^2 T_r) while the load rises (T_v <= T_r) and
(exp(-M_m^2 (T_v - T_r)) - exp(-M_m^2 T_v)) / (M_m^2 T_r) after, z the depth below the
drained top; the degree of consolidation U = 1 - mean(p) / p0 (the mean of sin(M z / H)
over the column is 1 / M).

Compared at every output (each 0.025 s, from T_v = 0.05): the pore pressure of every
particle against the series (the worst difference over the particles and times, relative to
q), the isochrones at T_v = 0.05, 0.1, 0.2, 0.5 and 1 (the same, per time), and U (its worst
difference). Gating, as issue 22 asks: within 2 % at all three resolutions, and the energy
residual within 0.1 % of the work of the load. Reported: the RMS difference over all
particles and outputs at each resolution and the observed order between them.

The closed form is quasi-static; the run is not: as the column drains, its skeleton takes the
load and it swings about the quasi-static settlement, which the flow damps out. With this
skeleton the swing is small; the worst difference falls from 0.23 % of q at H/dx = 20 to
0.17 % at 40 and stays at 0.16 % at 80 (observed order 0.4, then ~0: what is left at the
finer grids is that swing near T_v = 0.075, not the grid; on 2026-12-07). With a skeleton of
E = 10 MPa (a transit of 6 % of H^2 / c_v) the swing was 1.5 % of q at every resolution.

    .venv/bin/python validation/terzaghi/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/terzaghi.png.
Exit codes: 0 every target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import h5py  # noqa: E402
import numpy as np  # noqa: E402

from mpm_post import load_history  # noqa: E402
from mpm_post.io import list_outputs  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, load_json, relative, target, verdict, write_json)

RESULTS = HERE / "results"
CELLS = (20, 40, 80)
BAND = 0.02
ENERGY_BAND = 1e-3
ISOCHRONES = (0.05, 0.1, 0.2, 0.5, 1.0)
H = 1.0


def parameters(case):
    """(q, p0, c_v, ramp) of a case."""
    soil = case["materials"][0]
    water = case["pore_water"]
    saturated = water["materials"][0]
    modulus = soil["E"] * (1 - soil["nu"]) / ((1 + soil["nu"]) * (1 - 2 * soil["nu"]))
    storage = saturated["porosity"] / water["bulk_modulus"]
    p0 = case["loads"][0]["pressure"] * (1 / modulus) / (1 / modulus + storage)
    gamma_w = water["density"] * 9.80665
    cv = saturated["permeability"] / (gamma_w * (1 / modulus + storage))
    return case["loads"][0]["pressure"], p0, cv, case["loads"][0]["time_function"]["duration"]


def factor(mm, t, cv, ramp):
    """The time factor of mode M_m of the ramped load at time t."""
    tv, tr = cv * t / H**2, cv * ramp / H**2
    if tv <= tr:
        return (1 - np.exp(-mm**2 * tv)) / (mm**2 * tr)
    return (np.exp(-mm**2 * (tv - tr)) - np.exp(-mm**2 * tv)) / (mm**2 * tr)


def series(z, t, p0, cv, ramp):
    """Terzaghi's series for the ramped load: pore pressure at depth z, time t [Pa]."""
    p = np.zeros_like(z, dtype=float)
    for m in range(400):
        mm = np.pi * (2 * m + 1) / 2
        p += 2 * p0 / mm * np.sin(mm * z / H) * factor(mm, t, cv, ramp)
    return p


def degree(t, p0, cv, ramp):
    """Degree of consolidation U = 1 - mean p / p0 of the closed form."""
    mean = 0.0
    for m in range(400):
        mm = np.pi * (2 * m + 1) / 2
        mean += 2 * p0 / mm**2 * factor(mm, t, cv, ramp)
    return 1 - mean / p0


def analyse(output, case):
    """Per output from T_v = 0.05: (t, worst |p - series| / q, RMS / q, U run, U closed),
    and the profiles at the isochrone times."""
    q, p0, cv, ramp = parameters(case)
    rows, profiles = [], {}
    for time, path in list_outputs(output):
        if cv * time < 0.05 - 1e-9:
            continue
        with h5py.File(path, "r") as h5file:
            y = h5file["particles/position"][()][:, 1]
            p = h5file["particles/pore_pressure"][()]
        exact = series(H - y, time, p0, cv, ramp)
        rows.append((time, float(np.max(np.abs(p - exact)) / q),
                     float(np.sqrt(np.mean((p - exact) ** 2)) / q),
                     float(1 - np.mean(p) / p0), degree(time, p0, cv, ramp)))
        for tv in ISOCHRONES:
            # the output written at the first step past tv
            if -1e-6 <= cv * time - tv < 0.01 and tv not in profiles:
                order = np.argsort(y)
                profiles[tv] = (H - y[order], p[order] / q)
    return np.array(rows), profiles


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent folder of the outputs (default: outputs/, the runs "
                                 "overwrite outputs/terzaghi_n*)",
                     no_run_help="analyse the existing outputs")
    args = parser.parse_args(argv)
    parent = Path(args.output) if args.output else REPO / "outputs"
    runs, walls = {}, {}
    try:
        for n in CELLS:
            path = HERE / f"terzaghi_n{n}.json"
            case = load_json(path)
            output = parent / case["name"]
            if not args.no_run:
                if exe_missing(args.exe):
                    return 2
                walls[n] = run_mpm_geo(args.exe, path, output, overwrite=True,
                                       quiet=args.quiet, cwd=REPO)
            rows, profiles = analyse(output, case)
            history = load_history(output)
            runs[n] = (case, rows, profiles, history)
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    q, p0, cv, ramp = parameters(runs[CELLS[0]][0])
    results, per_run = [], {}
    for n in CELLS:
        case, rows, profiles, history = runs[n]
        worst = float(rows[:, 1].max())
        rms = float(np.sqrt(np.mean(rows[:, 2] ** 2)))
        u_worst = float(np.max(np.abs(rows[:, 3] - rows[:, 4])))
        work = float(history["load_work"][-1])
        residual = float(history["residual"][-1])
        iso = {}
        for tv in ISOCHRONES:
            k = int(np.argmin(np.abs(rows[:, 0] * cv - tv)))
            iso[f"{tv:g}"] = float(rows[k, 1])
        per_run[n] = {"worst_over_q": worst, "rms_over_q": rms, "U_worst": u_worst,
                      "isochrone_worst_over_q": iso, "residual_over_work": residual / work,
                      "viscous_over_work": float(history["viscous_work"][-1] / work),
                      "wall_time_s": walls.get(n)}
        results.append(target(f"H/dx = {n}: worst abs(p - series) / q, T_v 0.05 .. 1", worst, 0.0,
                              f"<= {BAND:.0%}", worst <= BAND, True,
                              "every particle at every output against Terzaghi's series",
                              unit="%"))
        results.append(target(f"H/dx = {n}: worst abs(U - U_series)", u_worst, 0.0,
                              f"<= {BAND:.0%}", u_worst <= BAND, True,
                              "degree of consolidation 1 - mean p / p0", unit="%"))
        results.append(target(f"H/dx = {n}: energy residual / work of the load",
                              residual / work, 0.0, f"abs <= {ENERGY_BAND:.1%}",
                              abs(residual / work) <= ENERGY_BAND, True,
                              "the flow's dissipation (viscous) and the water's stored energy "
                              "(elastic) close the balance", unit="%"))
    orders = []
    for a, b in zip(CELLS[:-1], CELLS[1:]):
        orders.append(float(np.log(per_run[a]["rms_over_q"] / per_run[b]["rms_over_q"])
                            / np.log(b / a)))
    worst_orders = [float(np.log(per_run[a]["worst_over_q"] / per_run[b]["worst_over_q"])
                          / np.log(b / a)) for a, b in zip(CELLS[:-1], CELLS[1:])]
    results.append(target("observed order of the RMS difference (20-40, 40-80)",
                          ", ".join(f"{o:.2f}" for o in orders), "",
                          "reported", True, False,
                          "from 40 cells on, the inertia of the column, not the grid, sets the "
                          "difference",
                          unit=""))
    passed = all(r["passed"] for r in results if r["gating"])

    figure = agg_figure(10.0, 4.4)
    left = figure.add_subplot(1, 2, 1)
    finest = runs[CELLS[-1]][2]
    z = np.linspace(0, H, 201)
    for k, tv in enumerate(ISOCHRONES):
        colour = f"C{k}"
        left.plot(series(z, tv / cv, p0, cv, ramp) / q, z, color=colour, lw=1.0,
                  label=f"T_v = {tv:g}")
        if tv in finest:
            depth, ratio = finest[tv]
            left.plot(ratio[::4], depth[::4], "o", color=colour, ms=3, mfc="none")
    left.invert_yaxis()
    left.set_xlabel("pore pressure p / q")
    left.set_ylabel("depth below the drained top z [m]")
    left.set_title(f"isochrones: series (lines), H/dx = {CELLS[-1]} (circles)", fontsize=9)
    left.grid(alpha=0.3)
    left.legend(fontsize=7)
    right = figure.add_subplot(1, 2, 2)
    tv_fine = np.linspace(0.03, 1.0, 195)
    right.plot(tv_fine, [degree(t / cv, p0, cv, ramp) for t in tv_fine], color="black",
               lw=1.0, label="series")
    for k, n in enumerate(CELLS):
        rows = runs[n][1]
        right.plot(rows[:, 0] * cv, rows[:, 3], "o", ms=2.5, mfc="none", color=f"C{k}",
                   label=f"H/dx = {n}")
    right.set_xlabel("time factor T_v = c_v t / H^2")
    right.set_ylabel("degree of consolidation U")
    right.set_title("U = 1 - mean p / p0", fontsize=9)
    right.grid(alpha=0.3)
    right.legend(fontsize=7)
    png = Path(args.results) / "terzaghi.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(png, dpi=110)

    worst_all = max(per_run[n]["worst_over_q"] for n in CELLS)
    worsts = ", ".join(f"{per_run[n]['worst_over_q']:.2%}" for n in CELLS)
    report = {
        "case": "terzaghi",
        "title": "Terzaghi's 1D consolidation (pore water)",
        "resolution": "full",
        "heading": "H / dx = 20, 40, 80; c_v = 1 m2/s, drained top",
        "case_files": [relative(HERE / f"terzaghi_n{n}.json") for n in CELLS],
        "headline": f"The pore pressures of every particle follow Terzaghi's series within "
                    f"{worsts} of the "
                    f"load at H/dx = {', '.join(str(n) for n in CELLS)} (T_v 0.05 to 1; "
                    f"target 2 %), the degree of consolidation within "
                    f"{max(per_run[n]['U_worst'] for n in CELLS):.2%}. Observed order "
                    f"{', '.join(f'{o:.2f}' for o in orders)} (RMS), "
                    f"{', '.join(f'{o:.2f}' for o in worst_orders)} (worst): the difference "
                    f"falls from 20 to 40 cells, then the column's swing about the "
                    f"quasi-static settlement (inertia, which the series does not have) sets "
                    f"it; energy residual "
                    f"{max(abs(per_run[n]['residual_over_work']) for n in CELLS):.3%} of the "
                    f"load's work at most.",
        "setup": {"rows": [
            ["column", "1 m, 1 cell wide, sliding walls and base; base impermeable, top "
                       "drained; no gravity, no damping"],
            ["soil", "linear_elastic E 1 GPa, nu 0, rho 2000 (saturated); n 0.3, k 1.1278e-5 "
                     "m/s; K_w 2 GPa: p0 = 0.870 q, c_v = 1 m2/s"],
            ["load", "q = 10 kPa on the top particles, ramped over 0.00204 s (4 H / c_u)"],
            ["grid", "2 x 2 particles per cell, cpGIMP, MUSL, CFL 0.5 (the pressure's "
                     "diffusion limit sets the step)"],
        ]},
        "metrics": {"per_resolution": {str(n): per_run[n] for n in CELLS},
                    "observed_order_rms": orders, "observed_order_worst": worst_orders,
                    "p0_over_q": p0 / q, "cv_m2_s": cv},
        "targets": results,
        "passed": passed,
        "wall_time_s": sum(w for w in walls.values() if w) if walls else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
    }
    write_json(Path(args.results) / "metrics.json", report)
    for r in results:
        print(f"{r['name']:<58} {r['value']!s:<24} {r['band']:<10} {verdict(r)}")
    print(report["headline"])
    print(f"worst over the resolutions: {worst_all:.2%}")
    print(f"terzaghi: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
