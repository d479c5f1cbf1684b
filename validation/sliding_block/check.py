#!/usr/bin/env python3
"""Verification: a block on a frictional floor under a tilted gravity (REFERENCES.md section 4).

An elastic block (0.2 m x 0.04 m, E = 100 MPa, nu = 0.3, rho = 2000 kg/m3) rests on the floor
(ymin, frictional with Coulomb coefficient mu) of a 1.2 m x 0.2 m grid of 20 mm cells; gravity
g = 9.81 m/s2 is tilted by theta = 30 deg, g (sin theta, -cos theta), so the floor is an
incline. Exact rigid-block solution, s the displacement along the floor:

    s(t) = g (sin theta - mu cos theta) t^2 / 2   while mu < tan(theta) = 0.577,
    s(t) = 0                                        when mu >= tan(theta) (the block sticks).

Case files sliding_block_mu_M.json for mu = 0, 0.2, 0.4 (slide) and 0.6 (sticks). The block is
flat: the resultant of its weight falls well inside the middle third of its base, so it slides
or sticks without tipping, as the analytic solution assumes. Compared: the mass-weighted mean
displacement along the floor at every output (every 25 ms) and at the end (0.5 s).

Expected errors (why the bands are what they are). Both come from the time step dt (CFL 0.5 of
the block's P-wave speed, 38.5 us), not from the cells, since the block moves rigidly:
- the particles move with the velocity at the end of each step, x += dt v(n+1), which puts the
  displacement ahead by a t dt / 2, a relative dt / t (8e-5 at 0.5 s);
- the friction limit of a floor node is mu times a running mean of its normal impulse (weight
  0.1 for the newest step, src/solver/mpm_transfer.f90): starting from zero, that mean misses
  the impulse of sum 0.9^n = 9 steps, so the block gains a velocity mu g cos(theta) 9 dt over
  the exact one, a relative error 18 mu g cos(theta) dt / (a t) at time t (0.3 % at mu = 0.4).
The gating band is the 2 % of the issue, several times these.

    .venv/bin/python validation/sliding_block/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/sliding_block.png.
Exit codes: 0 every target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import copy
import json
import math
import os
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post import list_outputs, load_particles  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, load_json, relative, target, verdict, write_json)

RESULTS = HERE / "results"
FRICTION = ["0.0", "0.2", "0.4", "0.6"]
CASES = [HERE / f"sliding_block_mu_{mu}.json" for mu in FRICTION]
SLIDE_BAND = 0.02          # issue target: s within 2 % of the exact slide
STICK_BAND = 2.0e-3        # sticking: |s| below 0.2 % of the frictionless slide
LOAD_LAG_STEPS = 9.0       # sum over n >= 1 of 0.9^n: steps of normal impulse the mean misses
CONTACT_TOLERANCE = 1.0e-3  # material within this fraction of dx of the floor touches it
# Informational runs of the sticking case (not targets): (key, label, change of the case).
STICK_VARIANTS = [
    ("cfl_0.2", "time.cfl 0.2", lambda c: c["time"].update(cfl=0.2)),
    ("damped", "local damping 0.05", lambda c: c.update(damping={"type": "local", "value": 0.05})),
    ("mu_0.8", "mu = 0.8", lambda c: c["domain"]["boundaries"]["ymin"].update(mu=0.8)),
]


def parameters(case):
    """Incline angle, g, friction, block and time step of a case."""
    gx, gy = case["gravity"]
    g = math.hypot(gx, gy)
    theta = math.atan2(gx, -gy)
    floor = case["domain"]["boundaries"]["ymin"]
    if not (isinstance(floor, dict) and floor.get("type", "").lower() == "frictional"):
        raise ValueError(f"{case['name']}: the floor (ymin) must be frictional")
    mu = float(floor["mu"])
    material = case["materials"][0]
    young, nu, rho = material["E"], material["nu"], material["rho"]
    wave = math.sqrt(young * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    dx = case["domain"]["dx"]
    body = case["bodies"][0]
    sticks = mu >= math.tan(theta)
    a = 0.0 if sticks else g * (math.sin(theta) - mu * math.cos(theta))
    return {"g": g, "theta": theta, "mu": mu, "sticks": sticks, "a": a, "dx": dx,
            "dt": case["time"].get("cfl", 0.5) * dx / wave, "wave_speed": wave,
            "tend": case["time"]["tend"], "young": young, "nu": nu, "rho": rho,
            "block": [body["max"][0] - body["min"][0], body["max"][1] - body["min"][1]],
            "s_free": 0.5 * g * math.sin(theta) * case["time"]["tend"] ** 2}


def expected_error(par, t):
    """Relative error of s(t) expected from the time step (module docstring)."""
    if par["sticks"] or par["a"] <= 0:
        return math.nan
    lag = 2.0 * LOAD_LAG_STEPS * par["mu"] * par["g"] * math.cos(par["theta"]) * par["dt"] \
        / (par["a"] * t)
    return par["dt"] / t + lag


def analyse(run_dir, par):
    outputs = list_outputs(run_dir)
    if len(outputs) < 3:
        raise FileNotFoundError(f"fewer than 3 particle outputs in {run_dir}")
    time, slide, lift, rise = [], [], [], []
    for t, path in outputs:
        p = load_particles(path)
        for field in ("mass", "displacement"):
            if field not in p:
                raise ValueError(f"{path}: field '{field}' missing; the case must write it")
        m = p["mass"]
        time.append(t)
        slide.append(float(np.sum(m * p["displacement"][:, 0]) / np.sum(m)))
        lift.append(float(np.max(p["displacement"][:, 1])))
        rise.append(float(np.sum(m * p["displacement"][:, 1]) / np.sum(m)))
    time, slide = np.array(time), np.array(slide)
    exact = 0.5 * par["a"] * time ** 2
    moving = time > 0
    metrics = {
        "mu": par["mu"],
        "sticks_exact": par["sticks"],
        "acceleration_exact_m_s2": par["a"],
        "time_s": float(time[-1]),
        "slide_m": float(slide[-1]),
        "slide_exact_m": float(exact[-1]),
        "slide_free_m": par["s_free"],
        "largest_lift_m": float(max(lift)),
        "centre_rise_m": float(rise[-1]),
        "dt_s": par["dt"],
    }
    if par["sticks"]:
        metrics["slip_over_free_slide"] = abs(slide[-1]) / par["s_free"]
    else:
        metrics["slide_relative_error"] = float(slide[-1] / exact[-1] - 1.0)
        metrics["slide_error_expected"] = expected_error(par, time[-1])
        metrics["slide_relative_error_max"] = float(
            np.max(np.abs(slide[moving] / exact[moving] - 1.0)[time[moving] >= 0.1]))
        # least-squares fit of s = a t^2 / 2
        x = 0.5 * time ** 2
        metrics["acceleration_fit_m_s2"] = float(np.dot(x, slide) / np.dot(x, x))
    return metrics, {"time": time, "slide": slide}


def run_variant(exe, case, output, overwrite):
    """Run a changed copy of a case (a dict) into ``output``; returns the wall time [s]."""
    with tempfile.TemporaryDirectory(prefix="sliding_block_") as tmp:
        path = Path(tmp) / f"{case['name']}.json"
        path.write_text(json.dumps(case), encoding="utf-8")
        return run_mpm_geo(exe, path, output, overwrite, True, cwd=REPO)


def stick_variants(args, base, case):
    """Informational runs of the sticking case; rows of a table and the slip series."""
    rows, series, wall = [], [], 0.0
    for key, label, change in STICK_VARIANTS:
        variant = copy.deepcopy(case)
        change(variant)
        variant["name"] = f"{case['name']}_{key}"
        par = parameters(variant)
        output = base / variant["name"]
        try:
            if not args.no_run:
                wall += run_variant(args.exe, variant, output, args.output is None)
            m, s = analyse(output, par)
        except (OSError, ValueError, RuntimeError, KeyError) as exc:
            print(f"sticking block, {label}: run failed: {exc}", file=sys.stderr)
            rows.append([label, "run failed", "", ""])
            continue
        rows.append([label, f"{m['slide_m'] * 1e3:.3f} mm",
                     f"{abs(m['slide_m']) / par['s_free']:.3%}",
                     f"{m['largest_lift_m'] * 1e3:.4f} mm"])
        series.append((label, s))
    return rows, series, wall


def targets_of(rows, pars):
    out = []
    for m, par in zip(rows, pars):
        mu = f"mu = {par['mu']:g}"
        if par["sticks"]:
            out.append(target(
                f"{mu}: sticks, slip at {m['time_s']:g} s", m["slide_m"], 0.0,
                f"abs <= {STICK_BAND * par['s_free'] * 1e3:.2f} mm "
                f"({STICK_BAND:.1%} of the free slide)",
                m["slip_over_free_slide"] <= STICK_BAND, True,
                f"mu >= tan(theta) = {math.tan(par['theta']):.3f}: the block must not slide. The "
                "running mean of the normal impulse reaches tan(theta) / mu of its steady value "
                "only after about 30 steps, during which the block starts to slip (about 1e-5 "
                "m); 0.2 % of the frictionless slide (dx / 16) is the criterion of "
                "tests/verification/test_sliding_block.f90", unit="mm"))
        else:
            out.append(target(
                f"{mu}: slide at {m['time_s']:g} s", m["slide_m"], m["slide_exact_m"],
                f"within {SLIDE_BAND:.0%}", abs(m["slide_relative_error"]) <= SLIDE_BAND, True,
                f"issue target; the expected error, from the time step only (dt / t for the "
                f"end-of-step position update, 18 mu g cos(theta) dt / (a t) for the start-up "
                f"lag of the contact's normal-impulse mean), is "
                f"{m['slide_error_expected']:+.2%} here; measured {m['slide_relative_error']:+.2%}",
                unit="m"))
    lift = max(m["largest_lift_m"] for m in rows)
    dx = pars[0]["dx"]
    allowed = CONTACT_TOLERANCE * dx
    out.append(target(
        "largest upward displacement of a particle", lift, None,
        f"<= {allowed * 1e3:.2f} mm", lift <= allowed, False,
        f"reported: the block should stay on the floor; a gap up to the contact tolerance "
        f"({CONTACT_TOLERANCE:g} dx) counts as touching, and its elastic strains are below 1e-5 "
        f"mm. Worst of the four runs", unit="mm"))
    return out


def plot(path, series, rows, pars, variants):
    figure = agg_figure(10.0, 3.4)
    slide, error, stick = figure.subplots(1, 3, width_ratios=[1.2, 1.0, 1.0])
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    t = np.linspace(0.0, pars[0]["tend"], 200)
    for s, m, par, colour in zip(series, rows, pars, colours):
        label = f"mu = {par['mu']:g}" + (" (sticks)" if par["sticks"] else "")
        slide.plot(t, 0.5 * par["a"] * t ** 2, color=colour, lw=1.2)
        slide.plot(s["time"], s["slide"], "o", ms=3.0, mfc="none", color=colour, label=label)
        if not par["sticks"]:
            ok = s["time"] >= 0.05
            te = s["time"][ok]
            error.plot(te, (s["slide"][ok] / (0.5 * par["a"] * te ** 2) - 1.0) * 100.0, "o-",
                       ms=3.0, lw=0.8, color=colour, label=label)
            error.plot(te, [expected_error(par, x) * 100.0 for x in te], ls="--", lw=0.8,
                       color=colour)
        else:
            stick.plot(s["time"], s["slide"] * 1e3, "o-", ms=3.0, lw=0.8, color=colour,
                       label=f"{label}: model")
            stick.axhline(STICK_BAND * par["s_free"] * 1e3, color="red", lw=0.8, ls="--",
                          label="band")
    slide.set_xlabel("time [s]")
    slide.set_ylabel("displacement along the floor [m]")
    slide.set_title("slide s(t): model (circles), g (sin - mu cos) t^2 / 2 (lines)", fontsize=8)
    slide.legend(fontsize=7)
    error.axhline(SLIDE_BAND * 100.0, color="red", lw=0.8, ls=":", label="band 2 %")
    error.set_ylim(-0.5, 2.5)
    error.set_xlabel("time [s]")
    error.set_ylabel("s / s_exact - 1 [%]")
    error.set_title("relative error (dashed: expected from dt)", fontsize=8)
    error.legend(fontsize=7)
    for (label, v), colour in zip(variants, ["0.5", "tab:purple", "tab:brown"]):
        stick.plot(v["time"], v["slide"] * 1e3, ".-", ms=2.0, lw=0.6, color=colour,
                   label=f"informational: {label}")
    stick.set_ylim(-0.1, 2.0 * STICK_BAND * pars[0]["s_free"] * 1e3)
    stick.set_xlabel("time [s]")
    stick.set_ylabel("slip [mm]")
    stick.set_title("the sticking block", fontsize=8)
    stick.legend(fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent folder of the runs' output folders (default: "
                                 "outputs/, each run overwriting outputs/<case name>); folders "
                                 "under a parent given here must not exist",
                     results_help="folder for metrics and plot (default: "
                                  "validation/sliding_block/results)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if not args.no_run and exe_missing(args.exe):
        return 2
    base = Path(args.output) if args.output else REPO / "outputs"
    rows, pars, series, walls = [], [], [], []
    try:
        for path in CASES:
            case = load_json(path)
            par = parameters(case)
            output = base / case["name"]
            if not args.no_run:
                walls.append(run_mpm_geo(args.exe, path, output, args.output is None,
                                         args.quiet, cwd=REPO))
            metrics, s = analyse(output, par)
            metrics["wall_time_s"] = walls[-1] if walls else None
            rows.append(metrics)
            pars.append(par)
            series.append(s)
    except (OSError, ValueError, RuntimeError, KeyError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    stick_case = next((load_json(p) for p, q in zip(CASES, pars) if q["sticks"]), None)
    variant_rows, variant_series, variant_wall = (
        stick_variants(args, base, stick_case) if stick_case else ([], [], 0.0))
    targets = targets_of(rows, pars)
    passed = all(t["passed"] for t in targets if t["gating"])
    par = pars[0]
    table = []
    for m, p in zip(rows, pars):
        if p["sticks"]:
            table.append([f"{p['mu']:g}", "0 (sticks)", "-", f"{m['slide_m'] * 1e3:.3f} mm",
                          "0", f"{m['slip_over_free_slide']:.3%} of the free slide", "-",
                          f"{m['largest_lift_m'] * 1e3:.3f} mm",
                          "-" if m["wall_time_s"] is None else f"{m['wall_time_s']:.1f} s"])
        else:
            table.append([f"{p['mu']:g}", f"{p['a']:.4f}", f"{m['acceleration_fit_m_s2']:.4f}",
                          f"{m['slide_m']:.5f} m", f"{m['slide_exact_m']:.5f} m",
                          f"{m['slide_relative_error']:+.3%}",
                          f"{m['slide_error_expected']:+.3%}",
                          f"{m['largest_lift_m'] * 1e3:.3f} mm",
                          "-" if m["wall_time_s"] is None else f"{m['wall_time_s']:.1f} s"])
    png = Path(args.results) / "sliding_block.png"
    mus = ", ".join(f"{p['mu']:g}" for p in pars)
    report = {
        "case": "sliding_block",
        "title": "Block sliding or sticking on a frictional floor under a gravity tilted by "
                 "30 deg (REFERENCES.md section 4, variant a)",
        "resolution": "4 friction coefficients",
        "heading": f"mu = {mus}, theta = "
                   f"{math.degrees(par['theta']):g} deg, {par['dx'] * 1e3:g} mm cells",
        "case_files": [relative(p) for p in CASES],
        "default_run": True,
        "setup": {"rows": [
            ["block", f"{par['block'][0]:g} m x {par['block'][1]:g} m, resting on the floor "
                      f"from x = 0.1 m; linear_elastic, E = {par['young']:.3g} Pa, "
                      f"nu = {par['nu']:g}, rho = {par['rho']:g} kg/m3"],
            ["grid", f"60 x 10 cells of {par['dx'] * 1e3:g} mm, 2 x 2 particles per cell "
                     "(80 particles)"],
            ["floor", f"ymin frictional, mu = {mus} (tan(theta) = "
                      f"{math.tan(par['theta']):.3f}); other faces free"],
            ["gravity", f"g = {par['g']:g} m/s2 tilted by theta = "
                        f"{math.degrees(par['theta']):g} deg: g (sin theta, -cos theta)"],
            ["solver", "MUSL, cpgimp, FLIP, CFL 0.5 "
                       f"(dt = {par['dt'] * 1e6:.1f} us at rest)"],
            ["simulated time", f"{par['tend']:g} s, outputs every 25 ms"],
        ]},
        "metrics": {"runs": rows},
        "targets": targets,
        "tables": [{
            "title": "Slide at the end per friction coefficient",
            "header": ["mu", "a exact [m/s2]", "a fitted [m/s2]", "s model", "s exact",
                       "error", "expected error", "largest lift", "mpm_geo wall time"],
            "rows": table},
            {"title": "Informational runs: the sticking block (mu = 0.6) with one change each "
                      "(not targets)",
             "header": ["run", "slip at 0.5 s", "of the free slide", "largest lift"],
             "rows": variant_rows}],
        "passed": passed,
        "wall_time_s": sum(walls) + variant_wall if walls else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
        "notes": [
            "The sticking block (mu = 0.6) still slips 0.06 mm in 0.5 s (1.2e-5 m of it in "
            "the first 25 ms, the start-up lag of the contact's normal-impulse mean, then about "
            "0.1 mm/s), 0.015 mm at CFL 0.2 and 0.056 mm with mu = 0.8: a creep that shrinks "
            "with the time step (about dt^1.5) and not with the margin of mu over tan(theta), so "
            "a truncation of the contact, not yet explained. Before the gap fix of issue 19 it "
            "slipped 0.21 mm.",
            "Before the gap fix of issue 19 (the contact now removes only the normal velocity "
            "beyond gap / dt), every block rose to the contact's gap tolerance (0.02 mm, the "
            "mean lift 2.0e-5 m in all four runs) and hovered there: the floor stopped every "
            "move into it and let every move out pass, so the ringing block ratcheted up. Now "
            "the mean lift is below 1.3e-7 m.",
            "Wall time: the four runs and the informational runs together.",
        ],
    }
    plot(png, series, rows, pars, variant_series)
    write_json(Path(args.results) / "metrics.json", report)
    for t in targets:
        ref = "" if t["reference"] is None else f" (exact {t['reference']:.5g})"
        print(f"{t['name']:<44} {t['value']:.5g}{ref}  [{t['band']}] {verdict(t)}")
    print(f"wrote {Path(args.results) / 'metrics.json'} and {png}")
    print(f"sliding_block: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
