#!/usr/bin/env python3
"""Validation: the cantilever under sudden gravity of Sadeghirad et al. (2011), three cell sizes.

The beam of REFERENCES.md section 8: 4 m x 1 m, clamped at x = 0, neo-Hookean E = 1 MPa,
nu = 0.3, rho = 1050 kg/m3, gravity 10 m/s2 from t = 0, plane strain, no damping. Published
peak deflection of the free end: 3.31 m (CPDI) and 3.32 m (cpGIMP). The combination the study
of issue 19 recommends (docs/study/cantilever.md): CPDI (cpdi), MUSL, FLIP, 2 x 2 particles per
cell, at 0.25, 0.125 and 0.0625 m cells, to t = 3 s (the peak comes at about 1.08 s; the runs
of the study that tore at the root did so at 1.25-1.5 s, on the way back up, so 3 s, a whole
swing and the rise to the second peak, is what shows the beam holds).
The case and the measures are those of the study (mpm_post.cantilever): the peak is the
largest downward displacement of the particle of the free end nearest the bottom corner, the
residual the ``residual`` of history.csv at the end over the largest drop of the potential
energy.

Pass bands (mpm_post.cantilever.peak_bands), derived, not picked:
- the uncertainty of the reference is the spread of the published peaks, |3.32 - 3.31| m;
- the discretisation error of each rung is estimated from the ladder itself (Richardson: the
  observed order from the two successive differences, the extrapolated peak at zero cell size,
  each rung's error |peak - extrapolated|), times Roache's factor of safety 1.25 (3 when the
  ladder shows no order);
- a peak passes when |peak - 3.31| <= spread + 1.25 x its error; the extrapolated peak when
  |extrapolated - 3.31| <= spread + the GCI of the finest rung; the ladder must converge (the
  finer difference smaller than the coarser one: otherwise there is no error estimate);
- the energy residual gets the relative peak band: under a sudden load an energy fraction e
  lost or gained moves the peak of a linear spring by the fraction e;
- every run ends with exit code 0 at t = 3 s;
- and the goal of issue 19, which this ladder must meet: every cell size within 2 % of 3.31 m
  with a residual under 1 %.

    .venv/bin/python validation/cantilever/check.py [--exe build/mpm_geo] [--no-run]
    .venv/bin/python validation/cantilever/check.py --bspline2-three (reported, not a target)
    .venv/bin/python validation/cantilever/check.py --write-cases    (regenerate the cases)

--bspline2-three runs the ladder of the combination recommended before CPDI, the quadratic
B-spline with 3 x 3 particles per cell (bspline2 with 2 x 2 tears at the root from 0.125 m
on), with the same derived bands but without the 2 x 2 goal: it writes
results/metrics_bspline2_three.json and exits 1 when a band is missed (an informational run).
Writes results/metrics.json and results/cantilever.png.
Exit codes: 0 every target met, 1 a target missed, 2 a run could not be analysed.
"""

import argparse
import json
import math
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

from mpm_post.cantilever import (  # noqa: E402
    PUBLISHED_PEAK, PUBLISHED_PEAK_CPGIMP, cantilever_case, measure, peak_bands)
from mpm_post.run import run_mpm_geo_status  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    PARENT_OUTPUT_HELP, agg_figure, common_arguments, exe_missing, load_json, relative, target,
    verdict, write_json)

RESULTS = HERE / "results"
LADDER = (0.25, 0.125, 0.0625)      # cell sizes [m], ratio 2
SCHEME, TRANSFER = "MUSL", "flip"
# the ladders: the target (CPDI 2 x 2) and the reported one (the quadratic B-spline 3 x 3):
# shape function, particles per cell and axis, whether its targets gate, results file, plot
LADDERS = {
    "cpdi": {"shape": "cpdi", "ppc": 2, "gating": True, "metrics": "metrics.json",
             "png": "cantilever.png"},
    "bspline2": {"shape": "bspline2", "ppc": 3, "gating": False,
                 "metrics": "metrics_bspline2_three.json",
                 "png": "cantilever_bspline2_three.png"},
}
TEND = 3.0                          # [s]
GOAL_PEAK = 0.02                    # issue 19's goal for 2 x 2 (relative to 3.31 m)
GOAL_RESIDUAL = 0.01


def case_path(dx, shape, ppc):
    """The committed case file of one rung."""
    return HERE / f"{cantilever_case(dx, shape, SCHEME, TRANSFER, ppc)['name']}.json"


def case_text(case):
    return json.dumps(case, indent=2) + "\n"


def write_cases():
    for ladder in LADDERS.values():
        for dx in LADDER:
            path = case_path(dx, ladder["shape"], ladder["ppc"])
            path.write_text(case_text(cantilever_case(dx, ladder["shape"], SCHEME, TRANSFER,
                                                      ladder["ppc"], tend=TEND)),
                            encoding="utf-8")
            print(f"wrote {relative(path)}")


def completed(row):
    """Whether a rung ran to the end: a run that stopped has no peak of the beam to compare."""
    return row["exit"] == 0 and row["end_s"] >= TEND - 1e-9


def ladder_targets(rows, gating=True):
    """The targets of a ladder, ``rows`` (coarse to fine) the measures of each rung with
    ``dx_m``, ``peak_m``, ``residual_rel``, ``exit`` and ``end_s``; ``gating`` whether they gate
    (the CPDI ladder) or are reported (the B-spline one). Returns (targets, bands).

    The bands come from the rungs that ran to the end (with two of them no order is observed
    and the factor of safety is 3); a rung that stopped fails its targets, and with fewer than
    two complete rungs there is no band at all. ``bands["per_row"]`` holds (peak band, residual
    band, estimated error) per row, NaN for a rung that stopped.
    """
    done = [r for r in rows if completed(r)]
    nan = (math.nan, math.nan, math.nan)
    bands = None
    if len(done) >= 2:
        bands = peak_bands([r["peak_m"] for r in done],
                           ratio=done[-2]["dx_m"] / done[-1]["dx_m"])
        fit = bands["richardson"]
        by_dx = {r["dx_m"]: (b, rb, e) for r, b, rb, e in zip(
            done, bands["peak_band_m"], bands["residual_band"], fit.errors)}
        bands["per_row"] = [by_dx.get(r["dx_m"], nan) for r in rows]
    out = []
    for index, r in enumerate(rows):
        dx = f"{r['dx_m']:g} m cells"
        band, res_band, err = bands["per_row"][index] if bands else nan
        if math.isnan(band):
            why = ("no band: this run stopped before the end" if not completed(r) else
                   "no band: fewer than two rungs ran to the end")
            out.append(target(f"peak deflection, {dx}", r["peak_m"], PUBLISHED_PEAK, "n/a",
                              False, gating, why + " (its largest deflection is not a peak of "
                              "the beam)", unit="m"))
            out.append(target(f"energy residual, {dx}", r["residual_rel"], 0.0, "n/a", False,
                              gating, why, unit="rel"))
        else:
            fit = bands["richardson"]
            out.append(target(
                f"peak deflection, {dx}", r["peak_m"], PUBLISHED_PEAK, f"+- {band:.4f} m",
                abs(r["peak_m"] - PUBLISHED_PEAK) <= band, gating,
                f"spread of the published peaks {bands['spread_m']:.3f} m + {fit.safety:g} x "
                f"the estimated discretisation error {err:.4f} m (|peak - extrapolated|, "
                f"{len(done)} complete rungs)", unit="m"))
            out.append(target(
                f"energy residual, {dx}", r["residual_rel"], 0.0, f"+- {res_band:.2%}",
                abs(r["residual_rel"]) <= res_band, gating,
                "the relative peak band: an energy fraction e lost or gained before the peak "
                "moves the peak of a suddenly loaded spring by the fraction e", unit="rel"))
        out.append(target(
            f"exit code 0 at t = {TEND:g} s, {dx}", float(r["exit"]), 0.0,
            "0", completed(r), gating,
            f"the run ends normally (reached {r['end_s']:.3f} s; 3: a particle left the grid "
            "or jumped more than a cell)"))
    if len(done) == 3:
        d = [done[i + 1]["peak_m"] - done[i]["peak_m"] for i in range(2)]
        ratio = abs(d[1]) / abs(d[0]) if d[0] != 0.0 else math.inf
        why = (f"successive differences of the peak {d[0] * 1e3:+.2f} mm and "
               f"{d[1] * 1e3:+.2f} mm; without convergence there is no estimate of the "
               "discretisation error")
    else:
        ratio = math.nan
        why = f"not observable: {len(done)} of the 3 runs ran to the end"
    out.append(target(
        "ladder converges: finer over coarser difference of the peak", ratio, None, "< 1",
        ratio < 1.0, gating, why))
    if bands is None:
        out.append(target("extrapolated peak (Richardson)", math.nan, PUBLISHED_PEAK, "n/a",
                          False, gating, "fewer than two rungs ran to the end", unit="m"))
    else:
        fit = bands["richardson"]
        out.append(target(
            "extrapolated peak (Richardson)", fit.extrapolated, PUBLISHED_PEAK,
            f"+- {bands['extrapolated_band_m']:.4f} m",
            abs(fit.extrapolated - PUBLISHED_PEAK) <= bands["extrapolated_band_m"], gating,
            (f"observed order {fit.order:.2f}" if math.isfinite(fit.order) else
             "no observed order") + f"; band: the spread {bands['spread_m']:.3f} m + the "
            f"GCI of the finest complete rung {fit.gci_fine:.4f} m", unit="m"))
    return out, bands


def goal_targets(rows):
    """The goal of issue 19 for the 2 x 2 ladder (gating: the CPDI ladder must meet it)."""
    out = []
    for r in rows:
        dx = f"{r['dx_m']:g} m cells"
        ok = r["exit"] == 0 and r["end_s"] >= TEND - 1e-9
        out.append(target(
            f"2 x 2: peak deflection, {dx}", r["peak_m"], PUBLISHED_PEAK,
            f"+- {GOAL_PEAK:.0%}", ok and abs(r["peak_m"] / PUBLISHED_PEAK - 1.0) <= GOAL_PEAK,
            True, "goal of issue 19 (every cell size within 2 % of 3.31 m); a run that stops "
            "fails it, whatever its peak", unit="m"))
        out.append(target(
            f"2 x 2: energy residual, {dx}", r["residual_rel"], 0.0, f"+- {GOAL_RESIDUAL:.0%}",
            abs(r["residual_rel"]) <= GOAL_RESIDUAL, True, "goal of issue 19", unit="rel"))
        out.append(target(
            f"2 x 2: exit code 0 at t = {TEND:g} s, {dx}", float(r["exit"]), 0.0, "0", ok,
            True, f"reached {r['end_s']:.3f} s"))
    return out


def run_ladder(args, ladder):
    """Run (unless --no-run) and measure a ladder (an entry of LADDERS); rows coarse to fine."""
    ppc = ladder["ppc"]
    base = Path(args.output) if args.output else REPO / "outputs"
    rows = []
    for dx in LADDER:
        path = case_path(dx, ladder["shape"], ppc)
        case = load_json(path)
        output = base / case["name"]
        status_path = output / "exit_code.txt"
        if args.no_run:
            wall = None
            code = int(status_path.read_text()) if status_path.is_file() else 0
        else:
            wall, code = run_mpm_geo_status(args.exe, path, output, args.output is None,
                                            args.quiet, cwd=REPO)
            status_path.write_text(f"{code}\n", encoding="utf-8")
        row = {"dx_m": dx, "ppc": ppc, "exit": code, "wall_time_s": wall}
        row.update(measure(output))
        rows.append(row)
    return rows


def plot(path, rows, bands, title):
    figure = agg_figure(10.0, 4.0)
    history, ladder = figure.subplots(1, 2)
    for r, colour in zip(rows, ["tab:blue", "tab:orange", "tab:green"]):
        history.plot(r["times_s"], r["tip_deflection_m"], color=colour, lw=1.0,
                     label=f"{r['dx_m']:g} m, peak {r['peak_m']:.4f} m"
                           + ("" if r["exit"] == 0 else f" (exit {r['exit']})"))
    history.axhline(PUBLISHED_PEAK, color="red", lw=0.8, ls="--", label="3.31 m (CPDI)")
    history.axhline(PUBLISHED_PEAK_CPGIMP, color="black", lw=0.8, ls=":",
                    label="3.32 m (cpGIMP)")
    history.set_xlabel("time [s]")
    history.set_ylabel("deflection of the free end [m]")
    history.set_title(title, fontsize=9)
    history.legend(fontsize=7)
    dx = [r["dx_m"] for r in rows]
    peaks = [r["peak_m"] for r in rows]
    if bands is not None:
        ladder.errorbar(dx, peaks, yerr=[b[0] for b in bands["per_row"]], fmt="o",
                        color="tab:blue",
                        capsize=3, label="peak, +- its band")
        fit = bands["richardson"]
        ladder.errorbar([0.0], [fit.extrapolated], yerr=[bands["extrapolated_band_m"]],
                        fmt="s", color="tab:green", capsize=3,
                        label=f"extrapolated (order {fit.order:.2f})")
    else:
        ladder.plot(dx, peaks, "o", color="tab:blue", label="peak")
    ladder.axhline(PUBLISHED_PEAK, color="red", lw=0.8, ls="--", label="3.31 m (CPDI)")
    ladder.axhline(PUBLISHED_PEAK_CPGIMP, color="black", lw=0.8, ls=":",
                   label="3.32 m (cpGIMP)")
    ladder.set_xlabel("cell size [m]")
    ladder.set_ylabel("peak deflection [m]")
    ladder.set_xlim(-0.02, 0.27)
    ladder.legend(fontsize=7)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=100)


def setup_rows(ladder, rows):
    ppc = ladder["ppc"]
    return {"rows": [
        ["beam", "4 m x 1 m, clamped at x = 0 (domain face xmin `fixed`), at y = 4..5 m in a "
                 "4.5 m x 5.5 m domain, the other faces free"],
        ["material", "neo_hookean: E = 1 MPa, nu = 0.3, rho = 1050 kg/m3; plane strain"],
        ["load", "gravity 10 m/s2 from t = 0, no damping"],
        ["grid", ", ".join(f"{r['dx_m']:g} m cells ({r['particles']} particles)"
                           for r in rows)],
        ["particles", f"{ppc} x {ppc} per cell, regular"],
        ["solver", f"{SCHEME}, {ladder['shape']}, {TRANSFER.upper()}, CFL 0.5"],
        ["simulated time", f"{TEND:g} s (peak at about {rows[0]['peak_time_s']:.2f} s)"],
    ]}


def table(rows):
    return {"title": "Per cell size",
            "header": ["cells", "particles", "peak", "peak - 3.31 m", "at", "residual (end)",
                       "residual (at peak)", "end", "exit", "mpm_geo wall time"],
            "rows": [[f"{r['dx_m']:g} m", r["particles"], f"{r['peak_m']:.4f} m",
                      f"{(r['peak_m'] / PUBLISHED_PEAK - 1.0) * 100:+.2f} %",
                      f"{r['peak_time_s']:.2f} s", f"{r['residual_rel'] * 100:+.3f} %",
                      f"{r['residual_at_peak_rel'] * 100:+.3f} %", f"{r['end_s']:.2f} s",
                      r["exit"], "-" if r["wall_time_s"] is None else
                      f"{r['wall_time_s']:.0f} s"] for r in rows]}


def strip(rows):
    return [{k: v for k, v in r.items() if k not in ("times_s", "tip_deflection_m")}
            for r in rows]


def rung_text(r):
    """One rung in a headline: its peak against 3.31 m, or where it stopped."""
    text = (f"{r['peak_m']:.4f} m ({(r['peak_m'] / PUBLISHED_PEAK - 1.0) * 100:+.2f} %) at "
            f"{r['dx_m']:g} m")
    if not completed(r):
        text += f" (stopped at {r['end_s']:.2f} s, exit {r['exit']})"
    return text


def headline_of(rows, bands, ladder, goal_met):
    """The agreement with the reference in one sentence (the first line of the section)."""
    text = "Peak deflection of the free end against 3.31 m: " + ", ".join(
        rung_text(r) for r in rows)
    if bands is not None:
        fit = bands["richardson"]
        text += f"; extrapolated {fit.extrapolated:.4f} m" + (
            f" (order {fit.order:.2f})" if math.isfinite(fit.order)
            else " (no order observed)")
    text += ". Energy residual " + ", ".join(f"{r['residual_rel'] * 100:+.3f} %" for r in rows)
    if ladder["gating"]:
        text += (f". Goal of issue 19 (2 x 2, within 2 % of 3.31 m, residual under 1 %) "
                 f"{'met' if goal_met else 'not met'}")
    return text + "."


def report_of(args, ladder, rows, targets, bands):
    gating = ladder["gating"]
    ppc = ladder["ppc"]
    results = Path(args.results)
    png = results / ladder["png"]
    passed = all(t["passed"] for t in targets)
    goal_met = all(t["passed"] for t in targets if t["name"].startswith("2 x 2"))
    walls = [r["wall_time_s"] for r in rows]
    headline = headline_of(rows, bands, ladder, goal_met)
    report = {
        "case": "cantilever",
        "title": "Cantilever under sudden gravity, Sadeghirad et al. (2011), REFERENCES.md "
                 "section 8: peak deflection of the free end at three cell sizes",
        # the option of a reported run (run_all.sh finds its time under that name)
        "resolution": (f"{LADDER[0]:g}-{LADDER[-1]:g} m cells" if gating else
                       "bspline2-three"),
        "heading": (f"0.25, 0.125 and 0.0625 m cells, {ladder['shape']}, {ppc} x {ppc} "
                    "particles per cell" + ("" if gating else
                                            " (reported: the combination recommended "
                                            "before CPDI)")),
        "headline": headline,
        "case_files": [relative(case_path(dx, ladder["shape"], ppc)) for dx in LADDER],
        "default_run": gating,
        "reported": not gating,
        "setup": setup_rows(ladder, rows),
        "metrics": {"resolutions": strip(rows)},
        "targets": targets,
        "tables": [table(rows)],
        "passed": passed,
        "wall_time_s": sum(walls) if None not in walls else None,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
        "notes": ["Wall time: the three cell sizes together."],
    }
    if bands is not None:
        fit = bands["richardson"]
        report["metrics"].update({
            "observed_order": fit.order, "extrapolated_peak_m": fit.extrapolated,
            "safety_factor": fit.safety, "gci_fine_m": fit.gci_fine,
            "reference_spread_m": bands["spread_m"]})
        order = (f"the observed order {fit.order:.2f}" if math.isfinite(fit.order) else
                 "no observed order (factor of safety 3, the error of a rung at least the "
                 "last difference)")
        report["notes"].insert(0, (
            "How the bands follow from the ladder: the spread of the published peaks "
            f"(3.32 - 3.31 = {bands['spread_m']:.2f} m, CPDI against cpGIMP) is the uncertainty "
            "of the reference; Richardson extrapolation of the peaks of the runs that reached "
            f"{TEND:g} s gives {order} and the peak at zero cell size {fit.extrapolated:.4f} m; "
            "each rung's band is the spread plus Roache's factor of safety "
            f"{fit.safety:g} times its estimated discretisation error (its distance to the "
            "extrapolated peak); the residual band is that band over 3.31 m."))
    plot(png, rows, bands, f"{ladder['shape']} MUSL FLIP {ppc} x {ppc}")
    return report


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS, output_help=PARENT_OUTPUT_HELP)
    parser.add_argument("--bspline2-three", action="store_true",
                        help="the quadratic B-spline 3 x 3 ladder, reported (not a target)")
    parser.add_argument("--write-cases", action="store_true",
                        help="write the case files from mpm_post.cantilever and exit")
    args = parser.parse_args(argv)
    if args.write_cases:
        write_cases()
        return 0
    if not args.no_run and exe_missing(args.exe):
        return 2
    ladder = LADDERS["bspline2" if args.bspline2_three else "cpdi"]
    try:
        rows = run_ladder(args, ladder)
    except (OSError, ValueError, KeyError, IndexError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    targets, bands = ladder_targets(rows, gating=ladder["gating"])
    if ladder["gating"]:
        targets += goal_targets(rows)
    name = ladder["metrics"]
    report = report_of(args, ladder, rows, targets, bands)
    write_json(Path(args.results) / name, report)
    for t in targets:
        ref = "" if t["reference"] is None else f" (reference {t['reference']:.4g})"
        print(f"{t['name']:<62} {t['value']:.5g}{ref}  [{t['band']}] {verdict(t)}")
    print(report["headline"])
    for note in report["notes"]:
        print(note)
    print(f"wrote {Path(args.results) / name}")
    print(f"cantilever ({report['resolution']}): {'PASS' if report['passed'] else 'FAIL'}")
    return 0 if report["passed"] else 1


if __name__ == "__main__":
    sys.exit(main())
