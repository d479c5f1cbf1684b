#!/usr/bin/env python3
"""Validation: a P wave through an elastic column onto an absorbing base (Lysmer-Kuhlemeyer).

A column 4 m high between sliding walls (1 x 80 cells of 0.05 m, 2 x 2 particles per cell,
cpGIMP, MUSL, FLIP), linear elastic, E = 1 MPa, nu = 0.3, rho = 1000 kg/m3: a confined P-wave
speed vp = sqrt(M / rho) = 36.69 m/s. No gravity, no damping. Its top is a rigid seismic face
that pushes one smooth compression pulse down the column, v(t) = -0.05 sin^2(pi t / 0.08) m/s
for t <= 0.08 s, then holds still (validation/absorbing_base/pulse.csv, rows every 1 ms). Its
base is an absorbing face with the column's own vp and vs (a matched dashpot). The pulse's tail
reaches the base at 0.08 + H / vp = 0.189 s; whatever the base reflects travels back up and
returns to it at 0.41 s, so at the end of the run (0.3 s) the energy left in the column
(kinetic + elastic) is what the base reflected.

Reference: a viscous boundary with the impedance of the material absorbs a plane wave at normal
incidence completely (Lysmer and Kuhlemeyer 1969); issue 22 asks for the reflected energy below
5 % of the incident. The incident energy is the work the top face did (load_work).

Gating: the reflected energy below 5 % of the incident; the energy balance closes to 1 % of it.
Reported: the same column on a sliding base, which reflects the pulse (the measure tells an
absorbing base from a reflecting one: it keeps nearly all of it).

S waves (absorbing_base_s.json, absorbing_base_s_sliding.json): the same column with periodic
side faces (a laterally infinite layer) and the same pulse pushed horizontally (scale [1, 0]):
vs = 19.61 m/s, the tail reaches the base at 0.08 + H / vs = 0.284 s, the reflection would be
back at the base at 0.69 s; the run ends at 0.45 s. Same targets.

Static load (absorbing_base_static_kv.json, absorbing_base_static_dashpot.json): a column 4 m
high (1 x 40 cells of 0.1 m, E = 100 MPa, nu = 0.3, rho = 2000) loaded by its weight from
t = 0 on an absorbing base with Kelvin-Voigt springs kn = G / R = 3.85 MPa/m, kt = kn / 2
(R = 10 m): it must settle by q / kn (q = rho g H, plus the column's compression below the
lowest particle) within 1 % and come to rest (its speed at 2 s below 1 % of the drift
speed q / (rho vp) a plain dashpot needs to carry q); the energy balance within 1 % of the
work of gravity. Reported: the same column on a plain dashpot, which sinks until its lowest
particles sit on the face.

    .venv/bin/python validation/absorbing_base/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/absorbing_base.png (P), results/metrics_s.json and
results/absorbing_base_s.png (S), results/metrics_static.json and
results/absorbing_base_static.png (static load).
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
CASES = {"absorbing": HERE / "absorbing_base.json", "sliding": HERE / "absorbing_base_sliding.json"}
CASES_STATIC = {"springs": HERE / "absorbing_base_static_kv.json",
                "dashpot": HERE / "absorbing_base_static_dashpot.json"}
CASES_S = {"absorbing": HERE / "absorbing_base_s.json",
           "sliding": HERE / "absorbing_base_s_sliding.json"}
REFLECTED_BAND = 0.05
RESIDUAL_BAND = 0.01


def energies(history):
    """(time, kinetic + elastic energy, work of the top face, energy the faces took, residual)."""
    return (np.asarray(history["time"]), np.asarray(history["kinetic_energy"])
            + np.asarray(history["elastic_energy"]), np.asarray(history["load_work"]),
            np.asarray(history["boundary_work"]), np.asarray(history["residual"]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent of the output folders (default: outputs/, the runs "
                                 "overwrite outputs/absorbing_base*)",
                     no_run_help="analyse the existing outputs")
    args = parser.parse_args(argv)
    return max(check_waves(args, CASES, "", "P", 36.6927),
               check_waves(args, CASES_S, "_s", "S", 19.6116),
               check_static(args))


def base_motion(output):
    """(times, vertical displacement and velocity of the lowest particle, its height at the
    start) of every output."""
    times, disp, vel = [], [], []
    lowest, height = None, None
    for time, path in list_outputs(output):
        with h5py.File(path, "r") as h5file:
            position = h5file["particles/position"][()]
            u = h5file["particles/displacement"][()]
            v = h5file["particles/velocity"][()]
        if lowest is None:
            lowest = int(np.argmin(position[:, 1]))
            height = float(position[lowest, 1])
        times.append(time)
        disp.append(float(u[lowest, 1]))
        vel.append(float(v[lowest, 1]))
    return np.array(times), np.array(disp), np.array(vel), height


def check_static(args):
    """A column under its weight on a Kelvin-Voigt base and on a plain dashpot; the exit
    code."""
    motions, walls = {}, 0.0
    try:
        for kind, path in CASES_STATIC.items():
            case = load_json(path)
            output = (Path(args.output) if args.output else REPO / "outputs") / case["name"]
            if not args.no_run:
                if exe_missing(args.exe):
                    return 2
                walls += run_mpm_geo(args.exe, path, output, overwrite=True, quiet=args.quiet,
                                     cwd=REPO) or 0.0
            motions[kind] = base_motion(output) + (load_history(output),)
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    case = load_json(CASES_STATIC["springs"])
    soil = case["materials"][0]
    face = case["domain"]["boundaries"]["ymin"]
    height = case["bodies"][0]["max"][1]
    young, nu, rho = soil["E"], soil["nu"], soil["rho"]
    modulus = young * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    g = -case["gravity"][1]
    weight = rho * g * height                      # the base's load per unit area [Pa]
    t, u, v, y0 = motions["springs"][:4]
    # the springs' settlement, and the column's own compression below the particle
    expected = -(weight / face["kn"] + rho * g * (height * y0 - y0**2 / 2) / modulus)
    settled = float(u[-1] / expected - 1.0)
    drift = weight / (rho * face["vp"])            # a plain dashpot's sinking speed [m/s]
    still = float(abs(v[-1]) / drift)
    td, ud, vd, _ = motions["dashpot"][:4]
    history = motions["springs"][4]
    residual = np.asarray(history["residual"])
    work = abs(float(history["potential_energy"][-1]))
    results = [
        target("Kelvin-Voigt base: settlement / (q / kn + compression) - 1", settled, 0.0,
               "abs <= 1%", abs(settled) <= 0.01, True,
               "the springs carry the weight q = rho g H: the base settles by q / kn, and the "
               "lowest particle by the column's compression below it too", unit="%"),
        target("Kelvin-Voigt base: speed at the end / a dashpot's drift q / (rho vp)", still,
               0.0, "< 1%", still < 0.01, True,
               "no drift: the loaded face comes to rest (a plain dashpot needs the speed q / "
               "(rho vp) to carry q)", unit="%"),
        target("plain dashpot: sinking of the lowest particle at the end [m]", float(ud[-1]),
               None, "reported", True, False,
               "a dashpot holds no static load: the column sinks until its lowest particles "
               "sit on the face (the wall keeps them in), dx / 4 = 0.025 m", unit="m"),
        target("energy residual / work of gravity (Kelvin-Voigt)",
               float(residual[-1] / work), 0.0, "abs <= 1%",
               abs(residual[-1] / work) <= 0.01, True,
               "the springs' stored energy and the dashpots' take are booked by the face "
               "(boundary_work)", unit="%"),
    ]
    passed = all(r["passed"] for r in results if r["gating"])
    figure = agg_figure(7.0, 4.4)
    axes = figure.add_subplot()
    axes.plot(t, -u * 1e3, color="tab:blue", label="Kelvin-Voigt base (kn, kt)")
    axes.plot(td, -ud * 1e3, color="tab:orange", label="plain dashpot")
    axes.axhline(-expected * 1e3, color="black", lw=0.8, ls="--",
                 label="q / kn + compression")
    axes.set_xlabel("time [s]")
    axes.set_ylabel("settlement of the lowest particle [mm]")
    axes.set_title("A column under its weight on an absorbing base", fontsize=10)
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8)
    png = Path(args.results) / "absorbing_base_static.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(png, dpi=110)
    report = {
        "case": "absorbing_base",
        "title": "A wave through an elastic column onto an absorbing base (reflected energy)",
        "resolution": "full",
        "heading": "static load: Kelvin-Voigt base against a plain dashpot",
        "case_files": [relative(CASES_STATIC["springs"]), relative(CASES_STATIC["dashpot"])],
        "headline": f"Under the column's weight the Kelvin-Voigt base settles to "
                    f"{-u[-1] * 1e3:.2f} mm against {-expected * 1e3:.2f} mm "
                    f"({settled:+.2%}) and comes to rest ({still:.1e} of a dashpot's drift "
                    f"speed); on a plain dashpot the column sinks until its lowest particles "
                    f"sit on the face ({-ud[-1] * 1e3:.1f} mm).",
        "setup": {"rows": [
            ["column", "4 m, 1 cell wide, sliding walls; gravity from t = 0, no damping"],
            ["soil", "linear_elastic E 100 MPa, nu 0.3, rho 2000: vp = 259.4, vs = 138.7 m/s"],
            ["base", "absorbing, vp and vs of the soil, springs kn = G / R = 3.85 MPa/m, kt = "
                     "kn / 2 (R = 10 m, alpha 1 and 1/2 in 2D); the reported run without "
                     "springs"],
            ["grid", "dx = 0.1 m, 2 x 2 particles per cell, cpGIMP, MUSL, FLIP, 2 s"],
        ]},
        "metrics": {"expected_m": expected, "settled_m": float(u[-1]),
                    "speed_over_drift": still, "dashpot_sinking_m": float(ud[-1])},
        "targets": results,
        "passed": passed,
        "wall_time_s": walls if not args.no_run else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
    }
    write_json(Path(args.results) / "metrics_static.json", report)
    for r in results:
        print(f"{r['name']:<60} {r['value']!s:<24} {r['band']:<10} {verdict(r)}")
    print(report["headline"])
    print(f"absorbing_base (static load): {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


def check_waves(args, cases, suffix, waves, speed):
    """Run and compare the columns of one kind of wave (P: suffix "", S: "_s", the soil's
    wave speed `speed`); the exit code."""
    runs = {}
    wall = None
    try:
        for kind, path in cases.items():
            case = load_json(path)
            output = (Path(args.output) if args.output else REPO / "outputs") / case["name"]
            if not args.no_run:
                if exe_missing(args.exe):
                    return 2
                seconds = run_mpm_geo(args.exe, path, output, overwrite=True,
                                      quiet=args.quiet, cwd=REPO)
                wall = (wall or 0.0) + (seconds or 0.0)
            runs[kind] = energies(load_history(output))
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    tend = load_json(cases["absorbing"])["time"]["tend"]

    t, left, work, taken, residual = runs["absorbing"]
    incident = float(work[-1])
    reflected = float(left[-1]) / incident
    closure = float(residual[-1]) / incident
    ts, lefts, works, _, _ = runs["sliding"]
    kept = float(lefts[-1]) / float(works[-1])
    results = [
        target("reflected energy / incident (absorbing base)", reflected, 0.0,
               f"< {REFLECTED_BAND:.0%}", reflected < REFLECTED_BAND, True,
               f"the energy left in the column at {tend:g} s, after the pulse has met the base "
               "and before its reflection returns, over the work of the top face (issue 22: "
               f"below 5 %; a matched dashpot absorbs a plane {waves} wave at normal incidence "
               "completely)"),
        target("energy residual / incident", closure, 0.0, f"abs <= {RESIDUAL_BAND:.0%}",
               abs(closure) <= RESIDUAL_BAND, True,
               "what the top face did (load_work) is what the base took (boundary_work) and "
               "what is left"),
        target("energy kept / incident (sliding base)", kept, 1.0, "reported", kept > 0.9,
               False, "the same pulse on a reflecting base: the measure tells the two apart"),
    ]
    passed = all(r["passed"] for r in results if r["gating"])

    figure = agg_figure(7.0, 4.4)
    axes = figure.add_subplot()
    axes.plot(t, left / incident, color="tab:blue", label="absorbing base: kinetic + elastic")
    axes.plot(t, taken / incident, color="tab:blue", ls="--",
              label="absorbing base: taken by the dashpots")
    axes.plot(ts, lefts / works[-1], color="tab:orange", label="sliding base: kinetic + elastic")
    axes.axvline(0.08 + 4.0 / speed, color="0.6", lw=0.8)
    axes.set_xlabel("time [s]")
    axes.set_ylabel("energy / work of the top face")
    axes.set_title(f"{waves} pulse onto an absorbing base: {reflected:.2e} of it reflected",
                   fontsize=10)
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8)
    png = Path(args.results) / f"absorbing_base{suffix}.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(png, dpi=110)

    report = {
        "case": "absorbing_base",
        "title": "A wave through an elastic column onto an absorbing base (reflected energy)",
        "resolution": "full",
        "heading": f"H / dx = 80 (0.05 m cells), {waves} waves",
        "case_files": [relative(cases["absorbing"]), relative(cases["sliding"])],
        "headline": f"The absorbing base reflects {reflected:.2e} of the incident pulse's energy "
                    f"(target below 5 %); the balance closes to {closure:+.1e} of it. On a "
                    f"sliding base the column keeps {kept:.3f} of it.",
        "setup": {"rows": [
            ["column", "4 m, 1 cell wide, " + ("periodic side faces" if waves == "S" else
                                               "sliding walls") + "; no gravity, no damping"],
            ["soil", f"linear_elastic E 1 MPa, nu 0.3, rho 1000: "
                     f"{'vs' if waves == 'S' else 'vp'} = {speed:.2f} m/s"],
            ["top", "seismic, rigid: v = -0.05 sin^2(pi t / 0.08) m/s for 0.08 s, then still, "
                    + ("horizontal" if waves == "S" else "vertical")],
            ["base", "absorbing, vp and vs of the soil (the reported run: sliding)"],
            ["grid", f"dx = 0.05 m, 2 x 2 particles per cell, cpGIMP, MUSL, FLIP, {tend:g} s"],
        ]},
        "metrics": {"incident_J_per_m": incident, "reflected_over_incident": reflected,
                    "residual_over_incident": closure, "sliding_kept_over_incident": kept},
        "targets": results,
        "passed": passed,
        "wall_time_s": wall,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
    }
    write_json(Path(args.results) / f"metrics{suffix}.json", report)
    for r in results:
        print(f"{r['name']:<48} {r['value']!s:<24} {r['band']:<10} {verdict(r)}")
    print(report["headline"])
    print(f"absorbing_base ({waves} waves): {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
