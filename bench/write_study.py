#!/usr/bin/env python3
"""Write docs/accuracy-vs-cost.md from the CSV files of the study (called by run_study.sh).

    .venv/bin/python bench/write_study.py docs/study/mms.csv docs/accuracy-vs-cost.md \
        [--column docs/study/column.csv] [--bui docs/study/bui.csv] [--times FILE]

mms.csv comes from bench/study_mms; column.csv and bui.csv from bench/study_cases.py (their
sections are written by bench/study_report.py); a missing file leaves its section out. --times:
lines "part seconds" (run_study.sh) for the run time of each part of the study.
docs/study/runout_refinement.md, written by hand (measurements the study does not make), is
appended as it is.
"""

import argparse
import datetime
import math
import platform
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "postproc"))

from mpm_post.study import (  # noqa: E402
    cheapest_for, combos, load_study, observed_order, pareto_front, plot_study)

import study_cases  # noqa: E402  (bench/, next to this file)
import study_report  # noqa: E402

TARGETS = [1e-3, 1e-4, 1e-5]
# the section on the runout of collapses under refinement (issue 19): measurements made by
# hand, not by the study, appended to the page as they are
RUNOUT_NOTES = REPO / "docs" / "study" / "runout_refinement.md"


def fmt(value, spec=".3g"):
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) \
        else format(value, spec)


def time_step_rule(row):
    """The time-step rule of a manufactured-solution run, from its cfl and tension_budget."""
    cfl = float(row.get("cfl") or "nan")
    budget = float(row.get("tension_budget") or "nan")
    text = f"CFL {cfl:g}" if math.isfinite(cfl) else "CFL"
    return text + (f" + tension (budget {budget:g})" if budget > 0 else "")


def section(rows, amplitude, figure, label):
    # the ladder only: the probes (mms_cfl, bar) are in mms_findings
    sel = [r for r in rows if r.get("problem", "mms") == "mms"
           and abs(r["amplitude"] - amplitude) <= 1e-12]
    lines = [f"## {label} (A = {amplitude:g} m)", "",
             f"![{label}]({figure.relative_to(REPO / 'docs')})", "",
             "| shape | scheme | cells | L2 error [m] | wall [s] | steps | time step |",
             "|---|---|---|---|---|---|---|"]
    for shape, scheme in combos(sel):
        for r in (r for r in sel if r["shape"] == shape and r["scheme"] == scheme):
            status = "" if r["status"] == "ok" else " (failed)"
            lines.append(f"| {shape} | {scheme} | {r['cells']} | {fmt(r['error_l2_m'])}{status} "
                         f"| {fmt(r['wall_s'])} | {r['steps'] or '-'} | {time_step_rule(r)} |")
    lines += ["", "Observed order (least-squares slope over the three finest resolutions; 2 is "
              "second order in h; a negative order means the error grows with refinement):", "",
              "| shape | scheme | order |", "|---|---|---|"]
    for shape, scheme in combos(sel):
        runs = [r for r in sel if r["shape"] == shape and r["scheme"] == scheme
                and r["status"] == "ok"]
        order = observed_order([r["cells"] for r in runs], [r["error_l2_m"] for r in runs])
        lines.append(f"| {shape} | {scheme} | {fmt(order, '.2f')} |")
    ok = [r for r in sel if r["status"] == "ok"]
    front = pareto_front([(r["wall_s"], r["error_l2_m"]) for r in ok])
    lines += ["", "Pareto front (no other run is both faster and more accurate): " + ", ".join(
        f"{ok[i]['shape']} {ok[i]['scheme']} {ok[i]['cells']} cells" for i in front) + ".", "",
        "Recommendation: the fastest run that reaches a target error.", "",
        "| target L2 error [m] | fastest run | its error [m] | wall [s] |", "|---|---|---|---|"]
    for target in TARGETS:
        best = cheapest_for(sel, target)
        if best is None:
            lines.append(f"| {target:g} | none reaches it | - | - |")
        else:
            lines.append(f"| {target:g} | {best['shape']} {best['scheme']}, {best['cells']} "
                         f"cells | {fmt(best['error_l2_m'])} | {fmt(best['wall_s'])} |")
    lines.append("")
    plot_study(sel, figure, f"{label}: error against run time")
    return lines


def tension_cost(rows):
    """Sentence on what the tension step costs: cpGIMP USF against USL at the finest level."""
    ladder = [r for r in rows if r.get("problem", "mms") == "mms" and r["status"] == "ok"
              and abs(r["amplitude"] - 0.05) <= 1e-12 and r["shape"] == "cpgimp"]
    pairs = {}
    for r in ladder:
        pairs.setdefault(r["cells"], {})[r["scheme"]] = r
    both = [c for c, p in pairs.items() if "USF" in p and "USL" in p]
    if not both:
        return ""
    cells = max(both)
    usf, usl = pairs[cells]["USF"], pairs[cells]["USL"]
    return (f"cpGIMP USF takes {usf['steps'] / usl['steps']:.1f} times the steps of USL at "
            f"{cells} cells ({usf['steps']} against {usl['steps']}), a factor that grows as "
            "1/dx. ")


def mms_findings(rows):
    """Why MUSL and USF lose accuracy at the large amplitude: the two probes of study_mms
    (problem "mms_cfl": 128 cells against the CFL factor; problem "bar": noise growth in a bar
    held at rest) and what they show."""
    cfl_rows = [r for r in rows if r.get("problem") == "mms_cfl" and r["status"] == "ok"]
    bars = [r for r in rows if r.get("problem") == "bar" and r["status"] == "ok"]
    if not cfl_rows and not bars:
        return []
    lines = [
        "### Why USF (and MUSL until it was fixed) lose accuracy at large deformation", "",
        "With the CFL step alone (CFL 0.2), cpGIMP with MUSL and USF at A = 0.05 converged to "
        "64 cells and then lost accuracy, while USL kept converging. MUSL now moves the "
        "particles with the remapped velocity that strains them, which removes the growth "
        "described here (the bar probe below shows it); USF keeps it. The cause is not the CFL "
        "formula (the wave speed of the deformed neo-Hookean material exceeds c by at most "
        "17 % here, and no particle moves more than 3 % of a cell per step) but a noise "
        "growth that MUSL and USF have with FLIP under tension. Each step these two schemes "
        "strain the particles (F, volume, cpGIMP domain, stress) with another nodal velocity "
        "than the one that moves them and does the work of the nodal forces: MUSL with the "
        "velocity remapped from the updated particle momenta, USF with the one of the start of "
        "the step. The two differ by O(dt) times the nodal acceleration, part of which is "
        "particle-scale noise that FLIP never damps (the null space of the transfer). Under a "
        "tensile stress sigma that mismatch feeds the noise at a rate of about "
        "sigma dt / (rho0 dx^2) (a dimensional estimate; the energy the stress puts into a "
        "mismatch of dt^2 a across a cell, against the kinetic energy of the mode). With a "
        "CFL step, dt ~ dx, the rate grows as 1/dx: the finer the grid, the more the noise "
        "grows over a period. USL strains and moves with the same velocity and shows none of "
        "it; compression damps instead of feeding.", ""]
    if cfl_rows:
        cfls = sorted({float(r["cfl"]) for r in cfl_rows}, reverse=True)
        cells = cfl_rows[0]["cells"]
        lines += [f"**The error against the CFL factor** (cpGIMP, A = 0.05, {cells} cells, the "
                  "CFL step alone, study_mms problem `mms_cfl`): at a fixed grid the MUSL and "
                  "USF errors fall much faster than a time error of order 1 or 2 would, since "
                  "the growth exponent is proportional to dt; USL's falls about in proportion "
                  "to dt, its first-order time error.", "",
                  "| scheme | " + " | ".join(f"CFL {c:g}" for c in cfls) + " |",
                  "|---|" + "---|" * len(cfls)]
        for scheme in dict.fromkeys(r["scheme"] for r in cfl_rows):
            errs = {float(r["cfl"]): r["error_l2_m"] for r in cfl_rows if r["scheme"] == scheme}
            lines.append(f"| {scheme} | " + " | ".join(f"{fmt(errs.get(c))} m" for c in cfls)
                         + " |")
        lines.append("")
    if bars:
        bar_schemes = list(dict.fromkeys(r["scheme"] for r in bars))
        lines += ["**Noise growth in a bar at rest** (cpGIMP, the strip held uniformly "
                  "stretched (F = 1.3, sigma = 0.27 E) or compressed (F = 0.7) between its "
                  "ends, particle velocities seeded with 1 mm/s of pseudo-random noise, 4 ms; "
                  "growth rate of the rms particle velocity fitted over the second half; "
                  "study_mms problem `bar`, `run_stretched_bar` in "
                  "src/verification/mpm_manufactured.f90):", "",
                  "| F | sigma [Pa] | cells | CFL | sigma+ dt / (rho0 dx^2) [1/s] | "
                  + " | ".join(f"{scheme} growth [1/s]" for scheme in bar_schemes) + " |",
                  "|---|---|---|---|---|" + "---|" * len(bar_schemes)]
        for key in dict.fromkeys((r["amplitude"], r["cells"], r["cfl"]) for r in bars):
            group = {r["scheme"]: r for r in bars if (r["amplitude"], r["cells"], r["cfl"]) == key}
            first = next(iter(group.values()))
            growth = [float(group[k]["growth_per_s"]) if k in group else math.nan
                      for k in bar_schemes]
            lines.append(f"| {key[0]:.3g} | {float(first['stress_pa']):.0f} | {key[1]} | "
                         f"{float(key[2]):g} | {float(first['estimate_per_s']):.0f} | "
                         + " | ".join(fmt(0.0 if abs(g) < 0.5 else g, ".0f") for g in growth)
                         + " |")
        ratios = [float(r["growth_per_s"]) / float(r["estimate_per_s"]) for r in bars
                  if float(r["estimate_per_s"]) > 0 and r["scheme"] == "USF"]
        if ratios:
            lines += ["", f"USF in tension: growth / estimate {min(ratios):.2f} to "
                      f"{max(ratios):.2f}; USL, MUSL and every compressed bar: no growth. The "
                      "ratio depends on how the particle pattern falls on the cells and on dt "
                      "(at small steps the rate falls further below the estimate), but the "
                      "estimate bounds every measured rate, which is what a time-step rule "
                      "needs."]
        lines.append("")
    lines += [
        "**The time-step rule of the study.** For USF the ladder adds the tension "
        "step dt <= B rho0 dx^2 / (sigma_max T) to the CFL step, sigma_max the largest tensile "
        "normal stress of the particles at that step and T the length of the run "
        "(`tension_time_step`). It makes the estimated growth rate B / T at every step, so "
        "the noise grows by at most about e^B over the run whatever the stress history; the "
        "study takes B = 4. It binds only where the stress is large: not at A = 0.001 "
        "(sigma up to 63 Pa); at A = 0.05 " + tension_cost(rows) + "USL and MUSL need no "
        "such step.", "",
        "**The remedy, adopted for MUSL**: moving the particles in MUSL with the remapped "
        "nodal velocity, the one that strains them, removes the growth (stretched bar: "
        "growth 0 at CFL 0.1 to 0.5; tests/verification/test_manufactured.f90 checks it) and lets the "
        "20 %-strain vibrating bar follow its nonlinear reference (validation/vibrating_bar). "
        "USF cannot use it, as it strains with the velocities of the start of the step. The "
        "APIC transfer "
        "(solver.transfer = \"apic\") also shows no growth in the stretched bar, for MUSL and "
        "USF alike, since it keeps no particle-scale velocity noise.", "",
        "**Fixed in the set-up** (for the record): the strip of this problem is one cell high. "
        "Its set-up used to release the transverse velocity that the sliding faces hold, and "
        "the strip then buckled like a beam of depth dx under the compression of the "
        "solution (sigma down to -0.39 E), from round-off, at a rate of about 0.3 c / dx; at "
        "256 cells that destroyed the MUSL and USF runs within half a period and made USL "
        "fail. tests/verification/test_manufactured.f90 checks that every node holds it now.", ""]
    return lines


# ---------------------------------------------------------------------------------------------
# self-weight column and Bui collapse (bench/study_cases.py, bench/study_report.py)
# ---------------------------------------------------------------------------------------------

# The run time the errors are set against, for the column and Bui: the CPU time of the mpm_geo
# process. On one thread it is the wall time the run takes on an idle core (start-up included,
# a few ms), and unlike the wall time it does not grow when other programs share the cores.
COST = "cpu_s"
COST_LABEL = "CPU time [s]"
TIMING_NOTE = (
    "Run time: the CPU time of the mpm_geo process on one thread (OMP_NUM_THREADS=1), which "
    "is the wall time on an otherwise idle core (start-up included); it is used rather than "
    "the wall time because other programs may share the cores during `make study`. The tables "
    "also give the wall time of the time loop as mpm_geo reports it.")


def explain_column_stress(rows):
    """The stress error against the error of a stress constant in each cell (dx / 4H)."""
    ok = [r for r in rows if study_report.usable(r, "stress_l2_rel", COST)]
    if not ok:
        return []
    ratios = [r["stress_l2_rel"] / (r["dx_m"] / (4 * study_cases.COLUMN_HEIGHT)) for r in ok]
    return [f"The stress error divided by dx / (4 H) is {min(ratios):.3g} to {max(ratios):.3g} "
            f"over all runs. dx / (4 H) is the error of a stress that is constant in each cell "
            f"and exact at its centre, seen by 2 particles per cell at +-dx/4 from it: the "
            f"particles of a cell share one strain (the gradient of the nodal displacement) "
            f"with either shape function, so a ratio near 1 means that this per-cell sampling, "
            f"first order by construction, is the whole stress error."]


def explain_column_settlement(rows):
    """USF against USL on the displacement, with the damping check made when setting up."""
    out = []
    for shape in dict.fromkeys(r["shape"] for r in rows):
        settle, stress = [], []
        for r in rows:
            if r["shape"] != shape or r["scheme"] != "USF" \
                    or not study_report.usable(r, "displacement_l2_rel", COST):
                continue
            twin = [o for o in rows if o["shape"] == shape and o["scheme"] == "USL"
                    and o["cells"] == r["cells"]
                    and study_report.usable(o, "displacement_l2_rel", COST)]
            if twin:
                settle.append(r["displacement_l2_rel"] / twin[0]["displacement_l2_rel"])
                stress.append(r["stress_l2_rel"] / twin[0]["stress_l2_rel"])
        if settle and min(settle) > 3:
            spread = max(abs(x - 1) for x in stress)
            same = (f", while their stress errors agree within {spread * 100:.2g} %"
                    if spread < 0.1 else "")
            out.append(f"{shape}: USF's displacement error is {min(settle):.3g} to "
                       f"{max(settle):.3g} times USL's at the same cells{same}.")
    if out:
        out.append("The likely reason: kinetic damping zeroes the particle velocities at each "
                   "peak of the kinetic energy. USF updates the stress with the grid velocity "
                   "before the step's forces and moves the particles with the one after, so "
                   "each reset leaves a mismatch of order dt between the strain the stress has "
                   "seen and the displacement; USL and MUSL use the same velocity for both. A "
                   "check made when the study was set up (not rerun here): with local damping "
                   "(0.15) instead, the displacement errors of cpGIMP at 8 and 16 cells were "
                   "0.30 % and 0.079 % with USF, 0.26 % and 0.058 % with USL. Local damping "
                   "leaves residual motion above the errors of the fine end of the ladder, "
                   "hence kinetic damping in the study.")
    return out


COLUMN_METRICS = [
    study_report.Metric(
        key="stress_l2_rel", title="Column: vertical stress",
        label="L2 stress error / (rho g H)", targets=[0.05, 0.02, 0.01, 0.005, 0.002, 0.001],
        figure="column_stress", explain=explain_column_stress,
        note="L2 norm over the particles (volume-weighted) of sigma_yy minus the exact "
             "-rho g (H - Y) at each particle's initial height Y, divided by rho g H."),
    study_report.Metric(
        key="displacement_l2_rel", title="Column: settlement profile",
        label="L2 displacement error / settlement", targets=[1e-2, 1e-3, 1e-4, 1e-5],
        figure="column_settlement", explain=explain_column_settlement,
        note="L2 norm over the particles (volume-weighted) of the vertical displacement minus "
             "the exact u_y(Y), divided by the largest exact settlement. (The settlement of the "
             "top row alone is in the table above; as a single signed value its error can pass "
             "near zero between two resolutions, so it is not the one fitted.)"),
]
COLUMN_COLUMNS = [("stress_l2_rel", "stress L2 / (rho g H)", 1.0),
                  ("base_stress_rel", "base stress (rel.)", 1.0),
                  ("settlement_rel", "settlement (rel.)", 1.0),
                  ("displacement_l2_rel", "displacement L2 (rel.)", 1.0),
                  ("cpu_s", "CPU [s]", 1.0)]


def explain_bui_toe(rows):
    """Self-convergence of the toe: its change between the two finest runs of each combination,
    and whether refinement moves it towards the measured toe."""
    import check  # validation/bui2008/check.py
    measured = check.experiment()["toe_m"]
    out = []
    for shape, scheme in study_report.combos(rows):
        runs = study_report.series(rows, shape, scheme, "toe_m", COST)
        if len(runs) < 2:
            continue
        a, b = runs[-2], runs[-1]
        change = (b["toe_m"] - a["toe_m"]) / measured
        towards = abs(b["toe_m"] - measured) < abs(a["toe_m"] - measured)
        side = "beyond" if b["toe_m"] > measured else "short of"
        out.append(f"{shape} {scheme}: the toe moves by {change:+.1%} of the measured toe from "
                   f"{a['cells']} to {b['cells']} cells, {'towards' if towards else 'away from'}"
                   f" the measurement, and ends {abs(b['toe_m'] / measured - 1):.1%} {side} "
                   f"it at {b['cells']} cells.")
    if out:
        out.append("A change between the two finest resolutions that is not small against the "
                   "remaining error means the runs are not yet converged in h; a small change "
                   "with a remaining error is the error of the model (continuum, constant "
                   "friction), which refinement cannot remove.")
    return out


def bui_metrics(toe):
    return [
        study_report.Metric(
            key="error", title="Bui: toe of the deposit",
            label="relative toe error", targets=[0.2, 0.1, 0.05, 0.02, 0.01],
            figure="bui_toe", slopes=(1.0,), converges_to_zero=False, explain=explain_bui_toe,
            note="Front of the final deposit (contiguous from the wall, "
                 "mpm_post.profiles.toe_position as in validation/bui2008/check.py) against "
                 f"the measured toe: abs(toe - {toe:.4g} m) / {toe:.4g} m."),
        study_report.Metric(
            key="surface_rms_m", title="Bui: free surface", scale=1e3,
            label="free-surface RMS [mm]", targets=[10.0, 5.0, 3.0, 2.0, 1.5, 1.0],
            figure="bui_surface", slopes=(1.0,), converges_to_zero=False,
            note="RMS height difference between the simulated and the measured final free "
                 "surface at the measured abscissae (check.py's analysis)."),
    ]


BUI_COLUMNS = [("toe_m", "toe [m]", 1.0), ("error", "toe error (rel.)", 1.0),
               ("surface_rms_m", "surface RMS [mm]", 1e3),
               ("height_at_wall_m", "height at wall [m]", 1.0),
               ("volume_change", "volume change", 1.0), ("cpu_s", "CPU [s]", 1.0)]


def contention(rows):
    """Sentence on how far wall and CPU time differ (other programs sharing the cores)."""
    ratios = [r["wall_s"] / r["cpu_s"] for r in rows if r["status"] == "ok"
              and r.get("cpu_s", 0) > 0.5 and r["wall_s"] > 0]
    if not ratios:
        return []
    return [f"Wall time / CPU time (runs of more than 0.5 s CPU; CPU time includes the "
            f"start-up): {min(ratios):.2f} to {max(ratios):.2f}, median "
            f"{sorted(ratios)[len(ratios) // 2]:.2f}. Well above 1 the cores were shared with "
            f"other programs during the study and the wall times carry that noise.", ""]


def column_section(rows, figures):
    case = study_cases
    cells = sorted({r["cells"] for r in rows})
    lines = [
        "## Self-weight column", "",
        f"Laterally confined elastic column under its own weight (REFERENCES.md section 2, the "
        f"parameters of the CB-Geo benchmark): H = {case.COLUMN_HEIGHT:g} m, rho = "
        f"{case.COLUMN_RHO:g} kg/m3, E = {case.COLUMN_E / 1e6:g} MPa, nu = {case.COLUMN_NU:g}, "
        f"g = {case.GRAVITY:g} m/s2; sliding side walls, fixed base, "
        f"{case.COLUMN_WIDTH_CELLS} cells wide (the solution does not depend on the width), 2 "
        f"particles per cell and axis, CFL {case.COLUMN_CFL:g}, kinetic damping over "
        f"{case.COLUMN_PERIODS:g} periods 4H/c_p of the first mode (the column is at rest after "
        f"5: the errors at 5, 10, 20 and 40 periods agree to 1e-13). Cells over the height: "
        f"{', '.join(map(str, cells))}. Exact static solution at each particle's initial "
        f"height Y: sigma_yy = -rho g (H - Y); with nu = 0 and the Jaumann-rate elastic law, "
        f"u_y(Y) = (E / rho g)(exp(-rho g (H - Y) / E) - exp(-rho g H / E)) - Y (strain at "
        f"most 0.18 %, within 0.1 % of the small-strain formula). Runs under "
        f"{case.REPEAT_BELOW:g} s are repeated and the fastest of three kept "
        f"(`bench/study_cases.py column`). {TIMING_NOTE}", "",
        "The base stress column is the figure the CB-Geo benchmark publishes (linear shape "
        "functions: 4.85 % at 10 mm cells, 2.33 % at 5 mm, 1.08 % at 2.5 mm).", ""]
    lines += study_report.runs_table(rows, COLUMN_COLUMNS) + [""]
    lines += contention(rows)
    for metric in COLUMN_METRICS:
        lines += study_report.metric_section(rows, metric, figures, REPO / "docs", COST,
                                             COST_LABEL)
    return lines


def bui_section(rows, figures):
    import check  # validation/bui2008/check.py (study_cases put its folder on the path)
    case = check.load_case(check.CASE)
    exp = check.experiment()
    material = case["materials"][0]
    dxs = sorted({r["dx_m"] for r in rows}, reverse=True)
    lines = [
        "## Bui et al. (2008) collapse", "",
        f"The validation case `validation/bui2008/bui2008.json` (aluminium bars, Mohr-Coulomb "
        f"phi = {material['phi']:g} deg, E = {material['E'] / 1e6:g} MPa, separation "
        f"{str(material.get('separation', False)).lower()}; floor "
        f"{check.describe_floor(case)}; transfer {case['solver'].get('transfer', 'flip')}; "
        f"{case['time']['tend']:g} s) with only the shape function, the scheme and the cell "
        f"size changed: {', '.join(f'{dx * 1e3:g} mm' for dx in dxs)} "
        f"({', '.join(str(round(check.COLUMN_HEIGHT / dx)) for dx in dxs)} cells over the "
        f"column's height). Compared with the measured final deposit (toe {exp['toe_m']:.4g} m) "
        f"by the functions of validation/bui2008/check.py. One run each "
        f"(`bench/study_cases.py bui`). A failed run (mpm_geo stopped, for instance a particle "
        f"thrown out of the grid) is listed with its reason and left out of the fits. "
        f"{TIMING_NOTE}", ""]
    lines += study_report.runs_table(rows, BUI_COLUMNS) + [""]
    lines += contention(rows)
    for metric in bui_metrics(exp["toe_m"]):
        lines += study_report.metric_section(rows, metric, figures, REPO / "docs", COST,
                                             COST_LABEL)
    return lines


def at_a_glance(parts):
    """Per problem and error: observed orders, the Pareto front, the best run, the failures."""
    lines = ["## At a glance", "",
             "Per problem and error: the observed order of each shape function (least-squares "
             "over the whole ladder, the range over the three schemes; against an experiment "
             "it is only a trend), the combinations whose runs make up the Pareto front of "
             "error against CPU time (how many of their runs), the smallest error any run "
             "reached, and the runs that failed. The sections below give the details and the "
             "fastest run for each target error.", "",
             "| problem | error | order: linear | order: cpgimp | on the Pareto front "
             "| smallest error (run, CPU time) | failed runs |",
             "|---|---|---|---|---|---|---|"]
    for problem, rows, metrics in parts:
        for metric in metrics:
            table = study_report.orders(rows, metric.key)
            spans = []
            for shape in ("linear", "cpgimp"):
                values = [e["order"] for e in table
                          if e["shape"] == shape and math.isfinite(e["order"])]
                if not values:
                    spans.append("-")
                elif max(values) - min(values) < 0.005:
                    spans.append(f"{min(values):.2f}")
                else:
                    spans.append(f"{min(values):.2f} to {max(values):.2f}")
            front = study_report.front(rows, metric.key, COST)
            counts = {}
            for r in front:
                combo = f"{r['shape']} {r['scheme']}"
                counts[combo] = counts.get(combo, 0) + 1
            ranked = ", ".join(f"{k} ({v})" for k, v in
                               sorted(counts.items(), key=lambda kv: -kv[1])) or "-"
            best = (f"{study_report.fmt(front[-1][metric.key] * metric.scale)} "
                    f"({study_report.name(front[-1])}, {study_report.fmt(front[-1][COST])} s)"
                    if front else "-")
            failed = len(study_report.failures(rows))
            lines.append(f"| {problem} | {metric.label} | {spans[0]} | {spans[1]} | {ranked} "
                         f"| {best} | {failed} of {len(rows)} |")
    return lines + [""]


def read_times(path):
    times = {}
    if path and Path(path).is_file():
        for line in Path(path).read_text().splitlines():
            fields = line.split()
            if len(fields) == 2:
                times[fields[0]] = float(fields[1])
    return times


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mms_csv")
    parser.add_argument("page")
    parser.add_argument("--column", help="CSV of bench/study_cases.py column")
    parser.add_argument("--bui", help="CSV of bench/study_cases.py bui")
    parser.add_argument("--times", help="file of lines 'part seconds'")
    args = parser.parse_args(argv[1:])
    rows = load_study(args.mms_csv)
    page = Path(args.page)
    figures = REPO / "docs" / "study"
    column = (study_report.load_runs(args.column)
              if args.column and Path(args.column).is_file() else None)
    bui = study_report.load_runs(args.bui) if args.bui and Path(args.bui).is_file() else None
    times = read_times(args.times)
    problems = ["the 1D large-deformation manufactured solution of REFERENCES.md section 3 "
                "(Steffen, Kirby and Berzins 2008; neo-Hookean, nu = 0, one period, 2 "
                "particles per cell; CFL 0.2, and for USF also the tension time step "
                "explained below), at its large amplitude A = 0.05 m (strains up to 30 %) and "
                "at a small one; runs under 2 s are the fastest of three"]
    if column is not None:
        problems.append("the self-weight column (REFERENCES.md section 2): static stress and "
                        "settlement")
    if bui is not None:
        problems.append("the Bui et al. (2008) collapse: toe and free surface against the "
                        "experiment")
    lines = [
        "# Accuracy against cost", "",
        "Written by `make study` (`bench/run_study.sh`); do not edit by hand. Every shape "
        "function and update scheme over a ladder of resolutions, error against run time on "
        "one thread (the wall time of the manufactured solution's time loop; the CPU time of "
        "the single-threaded mpm_geo runs of the column and the Bui collapse, see there). The "
        "environment variables STUDY_PARTS, STUDY_COLUMN_CELLS and "
        "STUDY_BUI_DX choose the parts and ladders (`STUDY_BUI_DX=\"0.01 0.005\" make study` "
        "leaves out the Bui runs at 2.5 mm, which take most of the time); see "
        "bench/run_study.sh.", "",
        f"Last run: {datetime.date.today()}, {platform.machine()} with "
        f"{__import__('os').cpu_count()} cores."
        + (" Run time of the study: " + ", ".join(f"{k} {v / 60:.1f} min"
                                                   for k, v in times.items()) + "."
           if times else ""), "",
        "Problems: " + "; ".join(problems) + ".", "",
        "Expected physics, checked rather than assumed: cpGIMP about second order while the "
        "spatial error dominates; linear shape functions losing convergence under large "
        "deformation (cell crossing). The tables below show what the runs give.", ""]
    glance = []
    if column is not None:
        glance.append(("column", column, COLUMN_METRICS))
    if bui is not None:
        import check  # noqa: F401  (validation/bui2008, on the path through study_cases)
        glance.append(("Bui", bui, bui_metrics(check.experiment()["toe_m"])))
    if glance:
        lines += at_a_glance(glance)
    lines += section(rows, 0.05, figures / "mms_large.png", "Large deformation")
    lines += mms_findings(rows)
    lines += section(rows, 0.001, figures / "mms_small.png", "Small deformation")
    if column is not None:
        lines += column_section(column, figures)
    if bui is not None:
        lines += bui_section(bui, figures)
    # sections measured outside the study (the cantilever of issue 19), kept across make study
    kept = figures / "cantilever.md"
    if kept.exists():
        lines += ["", kept.read_text().rstrip("\n"), ""]
    # measurements made by hand, not by the study (issue 19: the runout under refinement)
    if RUNOUT_NOTES.is_file():
        lines += ["", RUNOUT_NOTES.read_text().rstrip("\n")]
    page.write_text("\n".join(lines) + "\n")
    print(f"wrote {page}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
