"""Accuracy against cost: observed convergence orders, Pareto fronts and recommendations.

Reads the CSV that the study programs print (bench/study_*.f90: one line per run with the
problem, the shape function, the scheme, the number of cells, the wall time and the error) and
writes the figures and the Markdown page of ``make study``.
"""

import csv
import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def load_study(path):
    """Rows of a study CSV as dicts with numeric fields converted; failed runs kept, marked."""
    rows = []
    with open(path, newline="") as handle:
        for row in csv.DictReader(handle):
            for key in ("amplitude", "wall_s", "error_l2_m", "error_max_m"):
                row[key] = float(row[key]) if row.get(key) else math.nan
            for key in ("cells", "particles", "steps"):
                row[key] = int(row[key]) if row.get(key) else 0
            rows.append(row)
    if not rows:
        raise ValueError(f"{path}: no study rows")
    return rows


def combos(rows):
    """The (shape, scheme) pairs of a study, in file order."""
    seen = []
    for row in rows:
        key = (row["shape"], row["scheme"])
        if key not in seen:
            seen.append(key)
    return seen


def observed_order(cells, errors, finest=3):
    """Least-squares slope of -log(error) against log(cells) over the finest points.

    Returns nan with fewer than two finite points. A slope of 2 is second order in h.
    """
    cells = np.asarray(cells, dtype=float)
    errors = np.asarray(errors, dtype=float)
    ok = np.isfinite(errors) & (errors > 0)
    cells, errors = cells[ok][-finest:], errors[ok][-finest:]
    if cells.size < 2:
        return math.nan
    slope = np.polyfit(np.log(cells), np.log(errors), 1)[0]
    return float(-slope)


def pareto_front(points):
    """Indices of the points (cost, error) that no other point beats in both, by cost."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def cheapest_for(rows, target):
    """The run with the smallest wall time whose L2 error is at most ``target`` (or None)."""
    ok = [r for r in rows if r["status"] == "ok" and r["error_l2_m"] <= target]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def plot_study(rows, path, title):
    """Error against wall time (log-log) per combination, the Pareto front marked, and error
    against the number of cells; written to ``path`` (PNG)."""
    fig = Figure(figsize=(10, 4))
    FigureCanvasAgg(fig)
    cost_ax, conv_ax = fig.subplots(1, 2)
    ok = [r for r in rows if r["status"] == "ok"]
    for shape, scheme in combos(rows):
        sel = [r for r in ok if r["shape"] == shape and r["scheme"] == scheme]
        if not sel:
            continue
        label = f"{shape} {scheme}"
        cost_ax.loglog([r["wall_s"] for r in sel], [r["error_l2_m"] for r in sel], "o-",
                       ms=3, lw=1, label=label)
        conv_ax.loglog([r["cells"] for r in sel], [r["error_l2_m"] for r in sel], "o-", ms=3,
                       lw=1, label=label)
    front = pareto_front([(r["wall_s"], r["error_l2_m"]) for r in ok])
    cost_ax.loglog([ok[i]["wall_s"] for i in front], [ok[i]["error_l2_m"] for i in front], "k--",
                   lw=1.5, label="Pareto front")
    cells = np.array(sorted({r["cells"] for r in ok}), dtype=float)
    if cells.size:
        ref = max(r["error_l2_m"] for r in ok if r["cells"] == cells[0])
        conv_ax.loglog(cells, ref * (cells[0] / cells) ** 2, "k:", lw=1, label="second order")
    cost_ax.set(xlabel="wall time [s]", ylabel="L2 displacement error [m]", title=title)
    conv_ax.set(xlabel="cells along the bar", ylabel="L2 displacement error [m]",
                title="convergence")
    conv_ax.legend(fontsize=7)
    cost_ax.legend(fontsize=7)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
