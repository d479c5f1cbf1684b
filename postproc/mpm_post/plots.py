"""The standard figures of a run or of a study, written as PNG files.

- ``plot_profile``: the free surface of a deposit against a measured (reference) profile;
- the energy balance: ``mpm_post.energy.plot_energy`` (kinetic, strain, potential, damping
  work and total against time, from history.csv);
- ``plot_convergence``: error against cell size (log-log) per label, with the fitted order
  (``mpm_post.study.fit_order``) and reference slopes;
- ``plot_error_vs_time``: error against run time (log-log) per label, with the Pareto front
  (``mpm_post.study.pareto_front``) marked;
- ``plot_load_displacement``: the load-displacement curve of a region of
  ``prescribed_motion`` (a footing, a plate) from the reaction and displacement columns of
  history.csv (``load_displacement`` reads them).

``load_convergence`` and ``load_costs`` read the CSV files of the last two. Every function uses
matplotlib's Agg canvas directly (no display needed, a caller's backend is left alone), creates
the parent folder of the image and returns its Path.
"""

import csv
import math
from pathlib import Path

import numpy as np

from .study import fit_order, pareto_front

DEFAULT_SLOPES = (1.0, 2.0)


def _figure(width=7.0, height=4.5):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def _save(figure, path):
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=120)
    return path


# ----------------------------------------------------------------------------- CSV tables
def _is_number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True


def _table(path, names, numeric, optional=0):
    """Columns ``names`` of a small CSV file: arrays where ``numeric``, lists of strings else.

    The last ``optional`` columns may be missing (empty strings then). Blank lines and lines
    starting with ``#`` are skipped; a first line none of whose numeric fields is a number is a
    header and skipped too. Errors name the file and the line.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"table not found: {path}")
    rows = []
    with open(path, newline="") as handle:
        for number, row in enumerate(csv.reader(handle), start=1):
            row = [field.strip() for field in row]
            if not any(row) or row[0].startswith("#"):
                continue
            if not len(names) - optional <= len(row) <= len(names):
                raise ValueError(f"{path}:{number}: expected the columns {','.join(names)}"
                                 f"{' (the last optional)' if optional else ''}, got "
                                 f"{len(row)} fields")
            rows.append((number, row + [""] * (len(names) - len(row))))
    if rows and not any(_is_number(rows[0][1][k]) for k in numeric):
        rows = rows[1:]  # the header
    if not rows:
        raise ValueError(f"{path}: no data row (columns: {','.join(names)})")
    columns = []
    for k, name in enumerate(names):
        if k not in numeric:
            columns.append([row[k] for _, row in rows])
            continue
        values = []
        for number, row in rows:
            if not _is_number(row[k]):
                raise ValueError(f"{path}:{number}: {name} '{row[k]}' is not a number")
            values.append(float(row[k]))
        columns.append(np.array(values))
    return columns


def load_convergence(path):
    """A convergence table: CSV lines ``h,error[,label]`` (header line optional).

    ``h``: cell size [m]; ``error``: the error of the run with that cell size; ``label``: the
    series it belongs to (a method, a shape function; empty or missing: one unnamed series).
    Returns ``(h, error, labels)``: two arrays and a list of strings.
    """
    h, error, labels = _table(path, ["h", "error", "label"], numeric=(0, 1), optional=1)
    return h, error, labels


def load_costs(path):
    """An accuracy-against-cost table: CSV lines ``label,error,wall_time`` (header optional).

    ``wall_time``: run time [s]. Returns ``(labels, error, wall_time)``.
    """
    labels, error, wall = _table(path, ["label", "error", "wall_time"], numeric=(1, 2))
    return labels, error, wall


def _series(labels, n):
    """Distinct labels in first-seen order and the indices of each."""
    labels = [""] * n if labels is None else [str(label) for label in labels]
    if len(labels) != n:
        raise ValueError(f"{len(labels)} labels for {n} points")
    groups = {}
    for i, label in enumerate(labels):
        groups.setdefault(label, []).append(i)
    return groups


# ----------------------------------------------------------------------------- figures
def plot_profile(path, x_surface, height, reference=None, particles=None, toe=None,
                 title=None):
    """The free surface of a deposit, with a reference profile and the particles if given.

    ``x_surface``, ``height`` [m]: the simulated surface (from free_surface); ``reference``:
    ``(x, height)`` of a measured surface [m]; ``particles``: ``(x, y)`` of the particles [m],
    drawn as small grey dots; ``toe`` [m]: the front of the deposit, a vertical line.
    """
    figure = _figure(8.0, 4.0)
    axes = figure.add_subplot()
    if particles is not None:
        axes.plot(particles[0], particles[1], ".", color="0.75", ms=1.5, label="particles")
    axes.plot(x_surface, height, color="black", lw=1.2, drawstyle="steps-mid",
              label="model: free surface")
    if reference is not None:
        axes.plot(reference[0], reference[1], "o-", color="red", ms=3, lw=1.2,
                  label="reference")
    if toe is not None and math.isfinite(toe):
        axes.axvline(toe, color="0.3", ls=":", lw=1.0, label=f"toe {toe:.4g} m")
    axes.set(xlabel="x [m]", ylabel="height [m]", title=title or "free surface")
    axes.set_aspect("equal", adjustable="datalim")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    return _save(figure, path)


def plot_convergence(path, h, errors, labels=None, slopes=DEFAULT_SLOPES, title=None,
                     ylabel="error"):
    """Error against cell size (log-log), one series per label, with fitted orders.

    ``h`` [m], ``errors``: one point per run; ``labels``: the series of each point (None: one
    series); ``slopes``: orders of the reference lines drawn from the coarsest, largest-error
    point. Returns ``(path, orders)``: ``orders[label] = (slope, standard_error)`` from
    fit_order, or ``(nan, nan)`` for a series with fewer than two usable points.
    """
    h = np.asarray(h, dtype=float)
    errors = np.asarray(errors, dtype=float)
    if h.shape != errors.shape or h.ndim != 1:
        raise ValueError(f"{h.size} cell sizes but {errors.size} errors")
    usable = np.isfinite(h) & np.isfinite(errors) & (h > 0) & (errors > 0)
    if not np.any(usable):
        raise ValueError("no point with a positive cell size and a positive error to plot")
    figure = _figure()
    axes = figure.add_subplot()
    orders = {}
    for label, index in _series(labels, h.size).items():
        index = [i for i in index if usable[i]]
        if not index:
            orders[label] = (math.nan, math.nan)
            continue
        index = sorted(index, key=lambda i: h[i])
        try:
            orders[label] = fit_order(h[index], errors[index])
        except ValueError:
            orders[label] = (math.nan, math.nan)
        slope, sigma = orders[label]
        name = label or "error"
        if math.isfinite(slope):
            name += f": order {slope:.2f}" + (f" ± {sigma:.2f}" if math.isfinite(sigma) else "")
        axes.loglog(h[index], errors[index], "o-", ms=4, lw=1.2, label=name)
    h_min, h_max = float(h[usable].min()), float(h[usable].max())
    anchor = float(errors[usable][h[usable] == h_max].max())
    line = np.array([h_min, h_max])
    for order, style in zip(slopes, [":", "--", "-.", (0, (1, 4))] * 4):
        axes.loglog(line, anchor * (line / h_max) ** order, color="0.4", ls=style, lw=1.0,
                    label=f"slope {order:g}")
    axes.set(xlabel="cell size h [m]", ylabel=ylabel, title=title or "convergence")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    return _save(figure, path), orders


def plot_error_vs_time(path, labels, errors, wall_times, title=None, ylabel="error"):
    """Error against run time (log-log), one series per label, the Pareto front marked.

    ``labels``: the series of each run; ``errors``; ``wall_times`` [s]. The Pareto front
    (pareto_front: the runs no other run beats in both time and error) is a dashed black line
    with circled points. Returns ``(path, front)``, front: indices of the runs on it by
    increasing run time.
    """
    errors = np.asarray(errors, dtype=float)
    wall_times = np.asarray(wall_times, dtype=float)
    if errors.shape != wall_times.shape or errors.ndim != 1:
        raise ValueError(f"{errors.size} errors but {wall_times.size} run times")
    usable = (np.isfinite(errors) & np.isfinite(wall_times) & (errors > 0)
              & (wall_times > 0))
    if not np.any(usable):
        raise ValueError("no run with a positive error and run time to plot")
    figure = _figure()
    axes = figure.add_subplot()
    for label, index in _series(labels, errors.size).items():
        index = sorted((i for i in index if usable[i]), key=lambda i: wall_times[i])
        if index:
            axes.loglog(wall_times[index], errors[index], "o-", ms=4, lw=1.0,
                        label=label or "runs")
    candidates = np.flatnonzero(usable)
    front = [int(candidates[k]) for k in
             pareto_front([(wall_times[i], errors[i]) for i in candidates])]
    axes.loglog(wall_times[front], errors[front], "k--", lw=1.2, label="Pareto front")
    axes.loglog(wall_times[front], errors[front], "o", ms=9, mfc="none", mec="black")
    axes.set(xlabel="run time [s]", ylabel=ylabel, title=title or "error against run time")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    return _save(figure, path), front


# ----------------------------------------------------------------- load-displacement curves
def region_names(history):
    """The regions of prescribed_motion of a history: the <name> of its displacement_<name>_x
    columns, in file order."""
    return [key[len("displacement_"):-2] for key in history
            if key.startswith("displacement_") and key.endswith("_x")]


def load_displacement(history, region=None, axis=None, width=None):
    """(displacement, load, region, axis) of a region of prescribed_motion in a history.

    ``region``: its name (default: the only one); ``axis``: "x", "y" or "z" (default: the
    last axis of the run, the vertical). The load is minus the reaction (the force the
    material applies on the region, positive when the region pushes into it) and the
    displacement minus the region's (positive when it moves down or backwards), per
    ``width`` (a pressure) when given. Errors name what the history holds.
    """
    names = region_names(history)
    if not names:
        raise ValueError("the history has no prescribed_motion region (no displacement_<name>_x "
                         "column)")
    if region is None:
        if len(names) > 1:
            raise ValueError(f"the history has several regions ({', '.join(names)}); choose one "
                             "with --region")
        region = names[0]
    if region not in names:
        raise ValueError(f"no region '{region}' in the history; its regions: {', '.join(names)}")
    if axis is None:
        axis = "z" if f"displacement_{region}_z" in history else "y"
    key = f"reaction_{region}_{axis}"
    if key not in history:
        raise ValueError(f"no column {key} in the history")
    load = -np.asarray(history[key], float)
    if width is not None:
        load = load / width
    return -np.asarray(history[f"displacement_{region}_{axis}"], float), load, region, axis


def plot_load_displacement(path, displacement, load, title=None, reference=None,
                           ylabel="load [N/m]"):
    """The load-displacement curve; ``reference`` (value, label) draws a horizontal line."""
    figure = _figure()
    axes = figure.add_subplot()
    axes.plot(np.asarray(displacement) * 1e3, load, color="black", lw=1.2, label="mpm-geo")
    if reference is not None:
        axes.axhline(reference[0], color="tab:red", ls="--", lw=1.0, label=reference[1])
        axes.legend(fontsize=8)
    axes.set_xlabel("displacement [mm]")
    axes.set_ylabel(ylabel)
    axes.grid(alpha=0.3)
    if title:
        axes.set_title(title, fontsize=10)
    return _save(figure, path)


# ------------------------------------------------------------- factor of safety (strength reduction)
def load_strength_reduction(run):
    """The trials of a strength-reduction run: a dict of arrays ``factor``, ``displacement``,
    ``kinetic_ratio``, ``fails`` (bool) and the list ``folder``, sorted by factor, from
    <run>/strength_reduction.csv (or that file itself)."""
    path = Path(run)
    if path.is_dir():
        path = path / "strength_reduction.csv"
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    if not rows:
        raise ValueError(f"{path}: no trial")
    missing = {"factor", "displacement", "kinetic_ratio", "fails", "folder"} - set(rows[0])
    if missing:
        raise ValueError(f"{path}: not a strength_reduction.csv (no column "
                         f"{', '.join(sorted(missing))})")
    rows.sort(key=lambda row: float(row["factor"]))
    return {"factor": np.array([float(r["factor"]) for r in rows]),
            "displacement": np.array([float(r["displacement"]) for r in rows]),
            "kinetic_ratio": np.array([float(r["kinetic_ratio"]) for r in rows]),
            "fails": np.array([r["fails"] == "1" for r in rows]),
            "folder": [r["folder"] for r in rows]}


def factor_of_safety(trials):
    """(holds, fails): the largest factor that held and the smallest that failed (None when
    there is none)."""
    held = trials["factor"][~trials["fails"]]
    failed = trials["factor"][trials["fails"]]
    return (float(held.max()) if held.size else None,
            float(failed.min()) if failed.size else None)


def plot_strength_reduction(path, trials, limit=None, reference=None, title=None):
    """Largest displacement of each trial against its factor (log scale), held trials as
    filled and failed ones as open circles; ``limit`` draws the displacement limit,
    ``reference`` (value, label) a vertical line at a reference factor of safety."""
    figure = _figure()
    axes = figure.add_subplot()
    f, u, fails = trials["factor"], trials["displacement"], trials["fails"]
    axes.semilogy(f, u, color="0.6", lw=0.8)
    axes.semilogy(f[~fails], u[~fails], "o", color="black", label="holds")
    axes.semilogy(f[fails], u[fails], "o", mfc="none", mec="tab:red", label="fails")
    if limit is not None:
        axes.axhline(limit, color="tab:red", ls=":", lw=1.0, label="displacement limit")
    if reference is not None:
        axes.axvline(reference[0], color="tab:blue", ls="--", lw=1.0, label=reference[1])
    axes.set_xlabel("strength reduction factor F")
    axes.set_ylabel("largest displacement at tend [m]")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    if title:
        axes.set_title(title, fontsize=10)
    return _save(figure, path)
