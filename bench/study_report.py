"""The column and Bui sections of docs/accuracy-vs-cost.md (imported by bench/write_study.py).

Reads the CSV files of bench/study_cases.py (one line per run: problem, shape, scheme, cells,
dx_m, wall_s, error columns, status, note) and turns one error column (a "metric") into a
Markdown section: the runs, the observed order of each shape function and scheme, the Pareto
front of error against wall time, a recommendation table (the fastest run reaching each target
error) and a short text of what the numbers show, worded from the numbers themselves. Fits,
fronts and figures are those of mpm_post (mpm_post.study.fit_order, pareto_front;
mpm_post.plots.plot_error_vs_time, plot_convergence).
"""

import csv
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if str(REPO / "postproc") not in sys.path:
    sys.path.insert(0, str(REPO / "postproc"))

import numpy as np  # noqa: E402

from mpm_post.plots import plot_convergence, plot_error_vs_time  # noqa: E402
from mpm_post.study import fit_order, observed_order, pareto_front  # noqa: E402

TEXT_FIELDS = ("problem", "shape", "scheme", "status", "note")
INT_FIELDS = ("cells", "particles", "steps")
# A local order below this counts as "no convergence" over that refinement step.
STALL_ORDER = 0.3


@dataclass
class Metric:
    """One error column of a study CSV and how to show it."""

    key: str              # CSV column
    title: str            # heading and figure title
    label: str            # table header / axis label, with its unit
    targets: list         # target errors of the recommendation table
    scale: float = 1.0    # shown value = stored value * scale (1000 for m -> mm)
    slopes: tuple = (1.0, 2.0)
    figure: str = ""      # file stem of its figures in docs/study
    note: str = ""        # one paragraph under the heading
    converges_to_zero: bool = True   # False: an error against an experiment
    explain: object = None  # callable(rows) -> further sentences for the findings, or None


# ---------------------------------------------------------------------------------------------
# reading
# ---------------------------------------------------------------------------------------------

def load_runs(path):
    """Rows of a study_cases.py CSV as dicts: numbers converted, empty fields nan (ints 0)."""
    rows = []
    with open(path, newline="", encoding="utf-8") as handle:
        for row in csv.DictReader(handle):
            for key, value in row.items():
                if key in TEXT_FIELDS:
                    row[key] = value or ""
                elif key in INT_FIELDS:
                    row[key] = int(float(value)) if value else 0
                else:
                    row[key] = float(value) if value else math.nan
            rows.append(row)
    if not rows:
        raise ValueError(f"{path}: no run in the file")
    return rows


def combos(rows):
    """The (shape, scheme) pairs of the rows, in file order."""
    seen = []
    for row in rows:
        if (row["shape"], row["scheme"]) not in seen:
            seen.append((row["shape"], row["scheme"]))
    return seen


def usable(row, key, cost="wall_s"):
    """A finished run with a finite, positive value of ``key`` and of its ``cost`` [s]."""
    value, wall = row.get(key, math.nan), row.get(cost, math.nan)
    return (row["status"] == "ok" and isinstance(value, float) and math.isfinite(value)
            and value > 0 and math.isfinite(wall) and wall > 0)


def series(rows, shape, scheme, key, cost="wall_s"):
    """The usable runs of one combination, coarse to fine (by decreasing dx)."""
    sel = [r for r in rows if r["shape"] == shape and r["scheme"] == scheme
           and usable(r, key, cost)]
    return sorted(sel, key=lambda r: -r["dx_m"])


# ---------------------------------------------------------------------------------------------
# analysis
# ---------------------------------------------------------------------------------------------

def local_orders(runs, key):
    """Order between each pair of successive resolutions: log(e1/e2) / log(h1/h2)."""
    return [math.log(a[key] / b[key]) / math.log(a["dx_m"] / b["dx_m"])
            for a, b in zip(runs, runs[1:])]


def orders(rows, key):
    """Per combination: the least-squares order over all its runs (and its standard error),
    over the finest three, and the local orders. Orders are in h: error ~ h**order."""
    table = []
    for shape, scheme in combos(rows):
        runs = series(rows, shape, scheme, key)
        entry = {"shape": shape, "scheme": scheme, "runs": len(runs), "order": math.nan,
                 "stderr": math.nan, "finest3": math.nan, "local": local_orders(runs, key)}
        if len(runs) >= 2:
            entry["order"], entry["stderr"] = fit_order([r["dx_m"] for r in runs],
                                                        [r[key] for r in runs])
            entry["finest3"] = observed_order([r["cells"] for r in runs],
                                              [r[key] for r in runs])
        table.append(entry)
    return table


def front(rows, key, cost="wall_s"):
    """The runs on the Pareto front of (``cost``, ``key``), cheapest first."""
    ok = [r for r in rows if usable(r, key, cost)]
    return [ok[i] for i in pareto_front([(r[cost], r[key]) for r in ok])]


def fastest_reaching(rows, key, target, cost="wall_s"):
    """The run with the smallest ``cost`` whose ``key`` is at most ``target`` (or None)."""
    ok = [r for r in rows if usable(r, key, cost) and r[key] <= target]
    return min(ok, key=lambda r: r[cost]) if ok else None


def failures(rows):
    return [r for r in rows if r["status"] != "ok"]


def short(note, length=160):
    """A run's note cut to ``length`` characters (the CSV keeps it whole)."""
    note = " ".join((note or "no reason given").split())
    return note if len(note) <= length else note[:length - 3].rstrip() + "..."


def name(row):
    return f"{row['shape']} {row['scheme']}, {row['cells']} cells"


def fmt(value, spec=".3g"):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return format(value, spec)


def describe_order(order):
    """Words for an observed order (in h)."""
    if not math.isfinite(order):
        return "no order (fewer than two runs)"
    if order < -STALL_ORDER:
        return "the error grows with refinement"
    if order < STALL_ORDER:
        return "no convergence"
    for target in (1, 2, 3):
        if abs(order - target) <= 0.3:
            return ["about first order", "about second order", "about third order"][target - 1]
    return f"order {order:.1f}"


def shape_ratios(rows, key, shapes):
    """Per scheme: [(cells, error of shapes[1] / error of shapes[0])] at equal cells."""
    out = {}
    for r in rows:
        if r["shape"] != shapes[1] or not usable(r, key):
            continue
        twin = [o for o in rows if o["shape"] == shapes[0] and o["scheme"] == r["scheme"]
                and o["cells"] == r["cells"] and usable(o, key)]
        if twin:
            out.setdefault(r["scheme"], []).append((r["cells"], r[key] / twin[0][key]))
    return out


def compare_shapes(rows, metric, shapes):
    """Sentences comparing the two shape functions at the same scheme and cells."""
    per_scheme = shape_ratios(rows, metric.key, shapes)
    if not per_scheme:
        return [f"No pair of finished {shapes[0]} and {shapes[1]} runs at the same scheme and "
                f"cells to compare."]
    ratios = [q for pairs in per_scheme.values() for _, q in pairs]
    if all(0.9 <= q <= 1.1 for q in ratios):
        return [f"Same scheme and cells, {shapes[1]} against {shapes[0]}: about the same error "
                f"(ratio {min(ratios):.3g} to {max(ratios):.3g} over {len(ratios)} "
                f"pair{'s' if len(ratios) > 1 else ''})."]
    medians = ", ".join(f"{scheme} {float(np.median([q for _, q in pairs])):.3g}"
                        for scheme, pairs in per_scheme.items())
    finest = ", ".join(f"{scheme} {max(pairs)[1]:.3g} at {max(pairs)[0]} cells"
                       for scheme, pairs in per_scheme.items())
    return [f"Error of {shapes[1]} / error of {shapes[0]} at the same scheme and cells (below 1: "
            f"{shapes[1]} is more accurate): median over the ladder {medians}; at the finest "
            f"resolution both finished: {finest}."]


def reason(note):
    """The cause in a failed run's note, without mpm_geo's prefix and the advice after it:
    "mpm_geo exit code 3: step 12, t = 1.0E-01 s: particle 7 left the grid: position ..." gives
    "t = 0.1 s: particle 7 left the grid"."""
    text = " ".join((note or "").split())
    match = re.match(r"(?:mpm_geo exit code \d+: )?step \d+, t = ([-+0-9.eE]+) s: ([^:;]+)", text)
    if match:
        return f"t = {float(match.group(1)):.3g} s: {match.group(2).strip()}"
    return short(text)


def failure_summary(rows):
    """One sentence on the failed runs, grouped by combination, with their causes."""
    failed = failures(rows)
    if not failed:
        return "No run failed."
    groups = {}
    for r in failed:
        groups.setdefault(f"{r['shape']} {r['scheme']}", []).append(r)
    parts = []
    for combo, runs in groups.items():
        cells = ", ".join(str(r["cells"]) for r in runs)
        causes = "; ".join(f"{r['cells']} cells at {reason(r['note'])}" for r in runs)
        parts.append(f"{combo} at {cells} cells ({causes})")
    return (f"Failed runs ({len(failed)} of {len(rows)}), left out of the fits: "
            + "; ".join(parts) + ".")


def findings(rows, metric, table, pareto):
    """Sentences stating what the runs of one metric show, from the numbers alone."""
    key, out = metric.key, []
    for shape in dict.fromkeys(r["shape"] for r in rows):
        entries = [e for e in table if e["shape"] == shape and math.isfinite(e["order"])]
        if not entries:
            continue
        low, high = min(e["order"] for e in entries), max(e["order"] for e in entries)
        spread = f"{low:.2f}" if abs(high - low) < 0.005 else f"{low:.2f} to {high:.2f}"
        each = ", ".join(f"{e['scheme']} {e['order']:.2f}" for e in entries)
        if metric.converges_to_zero:
            words = " / ".join(sorted({describe_order(e["order"]) for e in entries}))
            out.append(f"{shape}: observed order {spread} over the whole ladder ({each}): "
                       f"{words}.")
        else:
            trend = ("falls" if low > 0 else "grows" if high < 0
                     else "falls for some schemes and grows for others")
            out.append(f"{shape}: the error against the experiment {trend} with refinement "
                       f"(slope {spread}: {each}).")
    # where a combination stops converging
    for e in table:
        runs = series(rows, e["shape"], e["scheme"], key)
        stalls = [(runs[i]["cells"], runs[i + 1]["cells"], p) for i, p in enumerate(e["local"])
                  if p < STALL_ORDER]
        if stalls:
            steps = ", ".join(f"{a} to {b} cells (local order {p:.2f})" for a, b, p in stalls)
            if metric.converges_to_zero:
                out.append(f"{e['shape']} {e['scheme']} stops converging: the error does not "
                           f"fall from {steps}.")
            else:
                out.append(f"{e['shape']} {e['scheme']}: the error against the experiment "
                           f"does not fall from {steps}.")
    # shapes against each other at the same resolution and scheme
    shapes = list(dict.fromkeys(r["shape"] for r in rows))
    if len(shapes) == 2:
        out += compare_shapes(rows, metric, shapes)
    # schemes against each other at the finest resolution every scheme reached
    for shape in shapes:
        finest = {}
        for e in (e for e in table if e["shape"] == shape):
            runs = series(rows, shape, e["scheme"], key)
            if runs:
                finest[e["scheme"]] = runs[-1]
        if len(finest) >= 2:
            cells = min(r["cells"] for r in finest.values())
            at = {s: next((r for r in series(rows, shape, s, key) if r["cells"] == cells), None)
                  for s in finest}
            at = {s: r for s, r in at.items() if r is not None}
            if len(at) >= 2:
                best = min(at, key=lambda s: at[s][key])
                worst = max(at, key=lambda s: at[s][key])
                ratio = at[worst][key] / at[best][key]
                if ratio < 1.1:
                    shown = ", ".join(f"{s} {fmt(at[s][key] * metric.scale)}" for s in at)
                    out.append(f"{shape} at {cells} cells: the schemes agree to within 10 % "
                               f"({shown}).")
                else:
                    out.append(f"{shape} at {cells} cells: {best} has the smallest error, "
                               f"{worst} a {ratio:.3g} times larger one.")
    if pareto:
        counts = {}
        for r in pareto:
            combo = f"{r['shape']} {r['scheme']}"
            counts[combo] = counts.get(combo, 0) + 1
        listed = ", ".join(f"{k} ({v})" for k, v in sorted(counts.items(), key=lambda kv: -kv[1]))
        runs = "1 run" if len(pareto) == 1 else f"{len(pareto)} runs"
        out.append(f"Pareto front: {runs}, by combination {listed}.")
    out.append(failure_summary(rows))
    return out


# ---------------------------------------------------------------------------------------------
# Markdown and figures
# ---------------------------------------------------------------------------------------------

def metric_section(rows, metric, figures, docs, cost="wall_s", cost_label="wall time [s]",
                   level="###"):
    """Markdown lines of one metric: figures, orders, Pareto front, recommendation, findings.

    ``figures``: folder of the PNG files; ``docs``: the folder the page lives in (for links);
    ``cost``: the column of the run time [s] the error is set against, ``cost_label`` its name.
    """
    key, scale = metric.key, metric.scale
    ok = [r for r in rows if usable(r, key, cost)]
    lines = [f"{level} {metric.title}", ""]
    if metric.note:
        lines += [metric.note, ""]
    if not ok:
        return lines + ["No run finished with a usable error.", ""]
    cost_png = figures / f"{metric.figure}_cost.png"
    conv_png = figures / f"{metric.figure}_convergence.png"
    labels = [f"{r['shape']} {r['scheme']}" for r in ok]
    values = [r[key] * scale for r in ok]
    plot_error_vs_time(cost_png, labels, values, [r[cost] for r in ok],
                       title=f"{metric.title}: error against {cost_label.split(' [')[0]}",
                       ylabel=metric.label)
    plot_convergence(conv_png, [r["dx_m"] for r in ok], values, labels, slopes=metric.slopes,
                     title=f"{metric.title}: convergence", ylabel=metric.label)
    rel = Path(cost_png).relative_to(docs), Path(conv_png).relative_to(docs)
    lines += [f"![{metric.title}: error against run time]({rel[0]})", "",
              f"![{metric.title}: error against cell size]({rel[1]})", ""]

    table = orders(rows, key)
    what = ("a positive order means the error against the experiment falls with refinement; it "
            "tends to the model error, not to zero, so the order says little beyond the trend"
            if not metric.converges_to_zero else "2 is second order in h")
    lines += [f"Observed order (error ~ h^order; least-squares fit over all finished runs of the "
              f"combination with its standard error, over the finest three, and between each "
              f"pair of successive resolutions, coarse to fine; {what}):", "",
              "| shape | scheme | runs | order (all) | ± | order (finest 3) | local orders |",
              "|---|---|---|---|---|---|---|"]
    for e in table:
        lines.append(f"| {e['shape']} | {e['scheme']} | {e['runs']} | {fmt(e['order'], '.2f')} "
                     f"| {fmt(e['stderr'], '.2f')} | {fmt(e['finest3'], '.2f')} | "
                     f"{', '.join(f'{p:.2f}' for p in e['local']) or '-'} |")

    pareto = front(rows, key, cost)
    lines += ["", "Pareto front (no other run is both faster and more accurate), fastest first: "
              + ", ".join(f"{name(r)} ({fmt(r[key] * scale)}, {fmt(r[cost])} s)"
                          for r in pareto) + ".", "",
              "Recommendation: the fastest run that reaches each target error.", "",
              f"| target: {metric.label} | fastest run | its error | {cost_label} |",
              "|---|---|---|---|"]
    for target in metric.targets:
        best = fastest_reaching(rows, key, target / scale, cost)
        if best is None:
            lines.append(f"| {target:g} | none of the runs reaches it | - | - |")
        else:
            lines.append(f"| {target:g} | {name(best)} | {fmt(best[key] * scale)} | "
                         f"{fmt(best[cost])} |")
    lines += ["", "What the runs show (worded from the numbers above):", ""]
    sentences = findings(rows, metric, table, pareto)
    if metric.explain is not None:
        sentences += metric.explain(rows)
    lines += [f"- {sentence}" for sentence in sentences]
    lines.append("")
    return lines


def runs_table(rows, columns):
    """Markdown table of every run: cells, dx, particles, steps, wall time and ``columns``,
    a list of (CSV key, header, scale) shown as value * scale."""
    head = ["shape", "scheme", "cells", "dx [mm]", "particles", "steps", "wall [s]"]
    head += [header for _, header, _ in columns] + ["status"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for shape, scheme in combos(rows):
        for r in sorted((r for r in rows if r["shape"] == shape and r["scheme"] == scheme),
                        key=lambda r: -r["dx_m"]):
            status = "ok" if r["status"] == "ok" else f"failed: {reason(r['note'])}"
            if r["status"] == "ok" and r.get("note"):
                status += f" ({short(r['note'])})"
            cells = [shape, scheme, str(r["cells"]), fmt(r["dx_m"] * 1e3, ".4g"),
                     str(r["particles"] or "-"), str(r["steps"] or "-"), fmt(r["wall_s"])]
            cells += [fmt(r.get(k, math.nan) * s) for k, _, s in columns]
            lines.append("| " + " | ".join(cells + [status]) + " |")
    return lines
