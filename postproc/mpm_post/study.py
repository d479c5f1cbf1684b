"""Accuracy against cost: observed convergence orders, Pareto fronts and recommendations.

Reads the CSV that the study programs print (bench/study_*.f90: one line per run with the
problem, the shape function, the scheme, the number of cells, the wall time and the error) and
writes the figures and the Markdown page of ``make study``.
"""

import csv
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


SAFETY_FACTOR_THREE = 1.25  # Roache's factor of safety with three grids and an observed order
SAFETY_FACTOR_TWO = 3.0     # and without one (two grids, or a ladder that is not monotone)


class Richardson(NamedTuple):
    """Discretisation error of a ladder of refinements (coarse to fine, constant ratio).

    ``order`` the observed order (NaN when it cannot be observed), ``extrapolated`` the
    Richardson value at zero cell size, ``errors`` the estimated error |value - extrapolated|
    of each rung, ``safety`` the factor of safety used (1.25 or 3), ``monotone`` whether the
    successive differences have one sign and shrink, ``gci_fine`` the grid convergence index
    of the finest rung (safety x its estimated error, the uncertainty of ``extrapolated``).
    """

    order: float
    extrapolated: float
    errors: list
    safety: float
    monotone: bool
    gci_fine: float


def richardson(values, ratio=2.0):
    """Richardson extrapolation of the last three ``values`` (coarse to fine, cell ratio
    ``ratio``), after Roache's grid convergence index.

    When the last two differences have one sign and shrink, the observed order is
    p = ln(d_coarse / d_fine) / ln(ratio), the extrapolated value is
    v_fine + d_fine / (ratio^p - 1) and the factor of safety 1.25. Otherwise (or with two
    values) no order is observed: the extrapolated value is the finest, its error is taken as
    the last difference, and the factor of safety is 3.
    """
    v = [float(x) for x in values]
    if len(v) < 2:
        raise ValueError("richardson: at least two values are needed")
    d_fine = v[-1] - v[-2]
    d_coarse = v[-2] - v[-3] if len(v) >= 3 else math.nan
    monotone = (len(v) >= 3 and d_fine * d_coarse > 0.0 and abs(d_fine) < abs(d_coarse))
    if monotone:
        order = math.log(d_coarse / d_fine) / math.log(ratio)
        extrapolated = v[-1] + d_fine / (ratio ** order - 1.0)
        safety = SAFETY_FACTOR_THREE
        errors = [abs(x - extrapolated) for x in v]
    else:
        order = math.nan
        extrapolated = v[-1]
        safety = SAFETY_FACTOR_TWO
        # no asymptotic range: each rung's error at least the largest change seen below it
        errors = [max(abs(x - v[-1]), abs(d_fine)) for x in v]
    return Richardson(order, extrapolated, errors, safety, monotone, safety * errors[-1])


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


def fit_order(h, errors):
    """Least-squares line through (log h, log error): the observed order and its standard error.

    ``h``: cell sizes [m] (or any resolution measure; with a number of cells the slope is minus
    the order); ``errors``: the error of each run (> 0). Points with a non-finite or
    non-positive h or error (failed runs) are left out. Returns ``(slope, standard_error)``:
    error ~ C h**slope, so 2 is second order; the standard error of the slope is
    sqrt(sum(residual**2) / (n - 2) / sum((log h - mean)**2)), nan with exactly two points
    (a line through two points has no residual to estimate it from). Raises ValueError when
    fewer than two points with distinct h remain.
    """
    h = np.asarray(h, dtype=float).reshape(-1)
    errors = np.asarray(errors, dtype=float).reshape(-1)
    if h.shape != errors.shape:
        raise ValueError(f"{h.size} resolutions but {errors.size} errors")
    ok = np.isfinite(h) & np.isfinite(errors) & (h > 0) & (errors > 0)
    log_h, log_e = np.log(h[ok]), np.log(errors[ok])
    if log_h.size < 2 or np.ptp(log_h) == 0.0:
        raise ValueError(f"an order needs at least two points with different h and a positive "
                         f"error, got {log_h.size} usable of {h.size}")
    slope, intercept = np.polyfit(log_h, log_e, 1)
    if log_h.size == 2:
        return float(slope), math.nan
    residual = log_e - (slope * log_h + intercept)
    spread = np.sum((log_h - log_h.mean()) ** 2)
    return float(slope), float(np.sqrt(np.sum(residual**2) / (log_h.size - 2) / spread))


def observed_order(cells, errors, finest=3):
    """Least-squares slope of -log(error) against log(cells) over the finest points.

    Returns nan with fewer than two finite points. A slope of 2 is second order in h.
    """
    cells = np.asarray(cells, dtype=float)
    errors = np.asarray(errors, dtype=float)
    ok = np.isfinite(errors) & (errors > 0)
    cells, errors = cells[ok][-finest:], errors[ok][-finest:]
    if cells.size < 2 or np.ptp(cells) == 0.0:
        return math.nan
    return -fit_order(cells, errors)[0]


def pareto_front(points):
    """Indices of the points (cost, error) that no other point beats in both, by cost.

    Sorted by increasing cost (and so decreasing error); a point equal to or worse than a
    cheaper (or equally cheap) one in error is not on the front. Non-finite points are left out.
    """
    points = list(points)
    order = sorted((i for i in range(len(points))
                    if math.isfinite(points[i][0]) and math.isfinite(points[i][1])),
                   key=lambda i: (points[i][0], points[i][1]))
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
