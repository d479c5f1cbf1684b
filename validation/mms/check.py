#!/usr/bin/env python3
"""Verification: the 1D large-deformation manufactured solution (../shared/REFERENCES.md section 3).

u(X, t) = A sin(2 pi X / L) cos(c pi t / L) on a neo-Hookean strip (E = 10 kPa, nu = 0,
rho0 = 1 kg/m3, L = 1 m, c = 100 m/s) between fixed ends, driven by the manufactured body force,
one period (0.02 s), cpGIMP, 2 particles per cell and axis. The runs are made by
build/study_mms (bench/study_mms.f90 on src/verification/mpm_manufactured.f90) with its
command-line options, at 16, 32, 64, 128 and 256 cells:

- small amplitude A = 0.001 m (strains 0.6 %), CFL 0.2: the convergence order of cpGIMP, gated
  for MUSL (the solver's default) and USL;
- large amplitude A = 0.05 m (strains 31 %), CFL 0.2: USL gated; MUSL and USF with the CFL step
  alone reported (with FLIP they amplify particle noise under tension at about
  sigma dt / (rho0 dx^2), which the CFL step does not bound); MUSL with the tension time step
  (budget 4, docs/accuracy-vs-cost.md) gated.

    .venv/bin/python validation/mms/check.py [--exe build/mpm_geo] [--no-run] [--quiet]

--exe names mpm_geo as for every case; study_mms is taken from the same folder (or
--study-exe). Writes results/metrics.json, results/mms_convergence.png and results/runs.csv
(the runs, which --no-run analyses again). Exit codes: 0 every target met, 1 a target missed,
2 a run or the analysis failed.
"""

import argparse
import csv
import io
import math
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
RESULTS = HERE / "results"
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, target, verdict, write_json)

CELLS = [16, 32, 64, 128, 256]
CFL = 0.2
BUDGET = 4.0            # the study's tension budget (bench/study_mms.f90)
SMALL, LARGE = 0.001, 0.05
ORDER_SLACK = 0.3       # least-squares order over 5 levels: allowance below the expected order
# Series: (key, label, amplitude, scheme, tension budget or None)
SERIES = [
    ("small_musl", "A = 0.001, MUSL", SMALL, "MUSL", None),
    ("small_usl", "A = 0.001, USL", SMALL, "USL", None),
    ("small_usf", "A = 0.001, USF", SMALL, "USF", None),
    ("large_usl", "A = 0.05, USL", LARGE, "USL", None),
    ("large_musl", "A = 0.05, MUSL, CFL step", LARGE, "MUSL", None),
    ("large_usf", "A = 0.05, USF, CFL step", LARGE, "USF", None),
    ("large_musl_tension", f"A = 0.05, MUSL, tension step (budget {BUDGET:g})", LARGE, "MUSL",
     BUDGET),
]
# The runs, one study_mms call each: (amplitude, schemes, tension budget or None)
CALLS = [(SMALL, "USL,MUSL,USF", None), (LARGE, "USL,MUSL,USF", None), (LARGE, "MUSL", BUDGET)]


def run_study(exe, quiet):
    """Run study_mms for every call; the CSV lines (header once) and the wall time."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    header, lines, start = None, [], time.time()
    for amplitude, schemes, budget in CALLS:
        args = [str(exe), "--amplitude", f"{amplitude:g}", "--shapes", "cpgimp",
                "--schemes", schemes, "--cells", ",".join(map(str, CELLS)),
                "--cfl", f"{CFL:g}", "--repeat", "1"]
        if budget is not None:
            args += ["--tension-budget", f"{budget:g}"]
        if not quiet:
            print("running " + " ".join(args[1:]), flush=True)
        done = subprocess.run(args, capture_output=True, text=True, env=env, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"{exe} exited with {done.returncode}: {done.stderr.strip()}")
        out = done.stdout.strip().splitlines()
        header = out[0]
        lines += out[1:]
    return header + "\n" + "\n".join(lines) + "\n", time.time() - start


def load_runs(text):
    rows = []
    for row in csv.DictReader(io.StringIO(text)):
        for key in ("amplitude", "wall_s", "error_l2_m", "error_max_m", "cfl", "tension_budget"):
            row[key] = float(row[key]) if row.get(key) else math.nan
        for key in ("cells", "particles", "steps"):
            row[key] = int(row[key]) if row.get(key) else 0
        rows.append(row)
    return rows


def series_rows(rows, amplitude, scheme, budget):
    sel = [r for r in rows if r["problem"] == "mms" and abs(r["amplitude"] - amplitude) < 1e-12
           and r["scheme"] == scheme and r["shape"] == "cpgimp"
           and ((budget is None and not r["tension_budget"] > 0)
                or (budget is not None and abs(r["tension_budget"] - budget) < 1e-12))]
    return sorted(sel, key=lambda r: r["cells"])


def fit(cells, errors):
    """Least-squares error = C h^p with h = 1 / cells: (p, C, standard error of p)."""
    h = 1.0 / np.asarray(cells, dtype=float)
    e = np.asarray(errors, dtype=float)
    ok = np.isfinite(e) & (e > 0)
    if ok.sum() < 2:
        return math.nan, math.nan, math.nan
    x, y = np.log(h[ok]), np.log(e[ok])
    p, c = np.polyfit(x, y, 1)
    if ok.sum() > 2:
        res = y - (p * x + c)
        se = math.sqrt(float(np.sum(res**2)) / (ok.sum() - 2) / float(np.sum((x - x.mean())**2)))
    else:
        se = math.nan
    return float(p), float(math.exp(c)), se


def analyse(rows):
    metrics = {}
    for key, label, amplitude, scheme, budget in SERIES:
        sel = series_rows(rows, amplitude, scheme, budget)
        cells = [r["cells"] for r in sel]
        errors = [r["error_l2_m"] if r["status"] == "ok" else math.nan for r in sel]
        order, const, stderr = fit(cells, errors)
        entry = {"label": label, "amplitude_m": amplitude, "scheme": scheme,
                 "tension_budget": budget, "cells": cells, "error_l2_m": errors,
                 "error_max_m": [r["error_max_m"] if r["status"] == "ok" else math.nan
                                 for r in sel],
                 "steps": [r["steps"] for r in sel], "wall_s": [r["wall_s"] for r in sel],
                 "status": [r["status"] for r in sel], "order": order, "order_stderr": stderr,
                 "halving_orders": [math.log2(a / b) if a > 0 and b > 0 else math.nan
                                    for a, b in zip(errors[:-1], errors[1:])]}
        if len(cells) >= 3:
            # the fit over all but the finest level, extrapolated to the finest
            p, c, _ = fit(cells[:-1], errors[:-1])
            entry["coarse_order"] = p
            entry["finest_predicted_m"] = c * (1.0 / cells[-1]) ** p if math.isfinite(p) \
                else math.nan
        metrics[key] = entry
    return metrics


def targets(m):
    def t(name, value, band, passed, gating, why, reference=None, unit=""):
        return target(name, value, reference, band, passed, gating, why, unit=unit)

    out = []
    low, high = 2.0 - ORDER_SLACK, 3.5
    for key, scheme in (("small_musl", "MUSL"), ("small_usl", "USL")):
        order = m[key]["order"]
        out.append(t(f"order, A = 0.001, {scheme}", order, f"{low:g} to {high:g}",
                     math.isfinite(order) and low <= order <= high, True,
                     "cpGIMP is second order in h while the spatial error dominates (the "
                     "time error of a CFL step is smaller here); the least-squares slope over "
                     f"5 levels is allowed {ORDER_SLACK:g} below 2. Above 3 the error would "
                     "fall faster than the first neglected term of the cell-size expansion: "
                     "the levels would be pre-asymptotic and the slope not an order", 2.0))
    e = m["small_musl"]
    bound = math.sqrt(2.0) * e["finest_predicted_m"]
    finest = e["error_l2_m"][-1]
    out.append(t(f"error at {CELLS[-1]} cells [m], A = 0.001, MUSL", finest,
                 f"<= sqrt(2) x {e['finest_predicted_m']:.3g} m (fit of the coarser levels, "
                 f"order {e['coarse_order']:.2f})", math.isfinite(finest) and finest <= bound,
                 True, "convergence goes on to the finest level: the fit over the four coarser "
                 "levels, extrapolated, bounds it within half an order of convergence lost over "
                 "the last halving (a factor sqrt(2)); a floor (round-off, the time error) would "
                 "break it"))
    order = m["small_usf"]["order"]
    out.append(t("order, A = 0.001, USF", order, f">= {low:g}",
                 math.isfinite(order) and order >= low, False,
                 "reported: USF updates the stress with the nodal velocities of the start of the "
                 "step, a lag of one step (an error O(dt) = O(h) at a fixed CFL) that takes over "
                 "from the O(h^2) spatial error on the finer levels", 2.0))
    for key, name in (("large_usl", "USL"), ("large_musl_tension",
                                             f"MUSL with the tension step (budget {BUDGET:g})")):
        order = m[key]["order"]
        ok = all(s == "ok" for s in m[key]["status"])
        out.append(t(f"order, A = 0.05, {name}", order, ">= 0.8, every level runs",
                     ok and math.isfinite(order) and order >= 0.8, True,
                     "at 31 % strain the time error dominates: with dt proportional to h (a "
                     "CFL step) an error O(dt) shows as first order in h (the study's probe at "
                     "128 cells: the USL error drops with the CFL factor); 0.2 below 1 for the "
                     "fit", 1.0))
    for key, name in (("large_musl", "MUSL"), ("large_usf", "USF")):
        e = m[key]["error_l2_m"]
        value = e[-1] / e[2] if len(e) == len(CELLS) and e[2] > 0 else math.nan
        out.append(t(f"error at {CELLS[-1]} / at {CELLS[2]} cells, A = 0.05, {name}, CFL step "
                     "alone", value, "< 1 (refinement helps)",
                     math.isfinite(value) and value < 1.0, False,
                     "reported, expected outside: with FLIP, MUSL (strained with the remapped "
                     "nodal velocity) and USF (with the one of the start of the step) move the "
                     "particles with another velocity than the one that strains them; under "
                     "tension that amplifies particle noise at about sigma dt / (rho0 dx^2), a "
                     "rate that a CFL step (dt ~ dx) lets grow as 1/dx: the tension step "
                     "(dt ~ dx^2) is what restores convergence"))
    return out


def plot(path, m):
    figure = agg_figure(10.0, 4.0)
    axes = figure.subplots(1, 2)
    groups = [("A = 0.001 m (strains 0.6 %)", ["small_musl", "small_usl", "small_usf"], 2.0),
              ("A = 0.05 m (strains 31 %)", ["large_usl", "large_musl_tension", "large_musl",
                                              "large_usf"], 1.0)]
    for ax, (title, keys, slope) in zip(axes, groups):
        for key in keys:
            e = m[key]
            cells = np.asarray(e["cells"], dtype=float)
            err = np.asarray(e["error_l2_m"], dtype=float)
            ok = np.isfinite(err)
            ax.loglog(cells[ok], err[ok], "o-", label=f"{e['label']} (order {e['order']:.2f})")
        e = m[keys[0]]
        c0, e0 = e["cells"][0], e["error_l2_m"][0]
        ref = np.array([CELLS[0], CELLS[-1]], dtype=float)
        ax.loglog(ref, e0 * (ref / c0) ** (-slope), "k:", lw=1, label=f"slope {slope:g}")
        ax.set_xticks(CELLS)
        ax.set_xticklabels([str(c) for c in CELLS])
        ax.minorticks_off()
        ax.set_xlabel("cells along the strip")
        ax.set_ylabel("L2 displacement error [m]")
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7)
        ax.grid(True, which="both", lw=0.3)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def fmt(value):
    return "-" if value is None or not math.isfinite(value) else f"{value:.3g}"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS, results_help="folder for metrics and plot",
                     exe_help="mpm_geo executable; study_mms is taken from its folder",
                     no_run_help="analyse results/runs.csv again", quiet_help="no progress lines")
    parser.add_argument("--study-exe", default=None, help="study_mms executable")
    args = parser.parse_args(argv)

    results = Path(args.results)
    runs_csv = results / "runs.csv"
    exe = Path(args.study_exe) if args.study_exe else Path(args.exe).parent / "study_mms"
    wall = None
    try:
        if args.no_run:
            text = runs_csv.read_text()
        else:
            if exe_missing(exe):
                return 2
            text, wall = run_study(exe, args.quiet)
            results.mkdir(parents=True, exist_ok=True)
            runs_csv.write_text(text)
        metrics = analyse(load_runs(text))
    except (OSError, ValueError, RuntimeError, KeyError, IndexError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    checked = targets(metrics)
    passed = all(c["passed"] for c in checked if c["gating"])
    table_rows = []
    for key, *_ in SERIES:
        e = metrics[key]
        table_rows.append([e["label"]] + [fmt(x) if s == "ok" else "failed"
                                          for x, s in zip(e["error_l2_m"], e["status"])]
                          + [fmt(e["order"])])
    halving_rows = [[metrics[key]["label"]] + [fmt(x) for x in metrics[key]["halving_orders"]]
                    for key, *_ in SERIES]
    report = {
        "case": "mms",
        "title": "1D large-deformation manufactured solution (Steffen, Kirby and Berzins 2008; "
                 "REFERENCES.md section 3): convergence of cpGIMP",
        "resolution": "full",
        "heading": f"cpGIMP, {', '.join(map(str, CELLS))} cells, CFL {CFL:g}",
        "case_files": ["src/verification/mpm_manufactured.f90", "bench/study_mms.f90"],
        "setup": {"rows": [
            ["problem", "u(X, t) = A sin(2 pi X / L) cos(c pi t / L), F = 1 + (2 pi A / L) "
                        "cos(2 pi X / L) cos(c pi t / L), sigma = E/2 (F - 1/F), body force "
                        "b = (c pi / L)^2 u (1 + 2 / F^2) at each particle's reference X"],
            ["material", "neo_hookean: E = 10 kPa, nu = 0, rho0 = 1 kg/m3 (c = 100 m/s)"],
            ["geometry", "strip L = 1 m, one cell high; ends held axially at and beyond "
                         "X = 0 and X = L, transverse velocity held at every node (sliding "
                         "faces)"],
            ["particles", "2 per cell and axis, started displaced, stretched and stressed as "
                          "u(X, 0), at rest"],
            ["solver", f"cpGIMP, FLIP; CFL {CFL:g} of dx / (c + \\|v\\|); the tension step "
                       f"adds dt <= {BUDGET:g} rho0 dx^2 / (sigma_max T), T = 0.02 s"],
            ["simulated time", "one period, 0.02 s"],
            ["error", "L2 = sqrt(mean over particles of (u_p - u(X_p, T))^2)"],
            ["runs", f"build/study_mms --amplitude A --shapes cpgimp --schemes ... --cells "
                     f"{','.join(map(str, CELLS))} --cfl {CFL:g} [--tension-budget "
                     f"{BUDGET:g}], one thread"],
        ]},
        "metrics": metrics,
        "targets": checked,
        "tables": [
            {"title": "L2 displacement error [m] and least-squares order",
             "header": ["series"] + [f"{c} cells" for c in CELLS] + ["order"],
             "rows": table_rows},
            {"title": "Order of each halving, log2(e(h) / e(h/2))",
             "header": ["series"] + [f"{a}-{b}" for a, b in zip(CELLS[:-1], CELLS[1:])],
             "rows": halving_rows},
        ],
        "passed": passed,
        "wall_time_s": wall,
        "threads": "1",
        "notes": [
            "Small amplitude: cpGIMP with USL and MUSL converges at an order near 3 rather "
            "than 2 over these levels; USF falls to first order on the finer ones (its "
            "one-step stress lag).",
            "Large amplitude: USL converges at first order (time error). With the CFL step "
            "alone MUSL and USF lose accuracy from 128 cells on (the tension-driven noise "
            "growth, rate up to about sigma dt / (rho0 dx^2)); the tension step restores "
            "convergence at the price of a step proportional to dx^2. See "
            "docs/accuracy-vs-cost.md for the measurements behind this.",
            "An earlier set-up left the transverse velocity free; the one-cell strip then "
            "buckled under the compression of the solution (sigma down to -0.39 E) at a rate "
            "of about 0.3 c / dx, which destroyed the 256-cell runs of every scheme. The "
            "set-up now holds it (tests/verification/test_manufactured.f90 checks that).",
        ],
    }
    png = results / "mms_convergence.png"
    report["plots"] = [png.name]
    plot(png, metrics)
    write_json(results / "metrics.json", report)
    for row in table_rows:
        print(" | ".join(str(c) for c in row))
    for c in checked:
        print(f"{c['name']:<62} {fmt(c['value']):>10}  {c['band']:<30} {verdict(c)}")
    print(f"wrote {results / 'metrics.json'} and {png}")
    print(f"mms: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
