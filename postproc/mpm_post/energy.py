"""Energy balance of a run, from the dict returned by load_history."""

from pathlib import Path

import numpy as np

# Columns of history.csv [J] (per unit thickness in 2D) and their labels in plots.
ENERGY_TERMS = {
    "kinetic_energy": "kinetic",
    "strain_energy": "strain",
    "potential_energy": "potential",
    "damping_work": "damping work",
    "total": "total",
}


def _column(history, name):
    if name not in history:
        raise KeyError(f"history has no '{name}' column (columns: {', '.join(history)})")
    return np.asarray(history[name], dtype=float)


def energy_drift(history):
    """Largest change of the total energy, relative to the largest kinetic + strain energy.

    ``max |total - total[0]| / max(max(kinetic_energy + strain_energy), tiny)``: 0 for an exactly
    conserving run; a dimensionless number comparable between runs of different sizes.
    """
    total = _column(history, "total")
    if total.size == 0:
        raise ValueError("history is empty: no energy drift to compute")
    mechanical = _column(history, "kinetic_energy") + _column(history, "strain_energy")
    scale = max(float(np.max(mechanical)), np.finfo(float).tiny)
    return float(np.max(np.abs(total - total[0])) / scale)


def plot_energy(history, path, title=None):
    """Plot every energy term of ``history`` against time into an image file; returns its Path.

    ``title``: an optional title of the plot (the run, its energy drift, ...).

    Uses matplotlib's Agg canvas directly, so no display is needed and the global backend of a
    calling program is left alone. The parent directory is created when missing.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    time = _column(history, "time")
    terms = [name for name in ENERGY_TERMS if name in history]
    if not terms:
        expected = ", ".join(ENERGY_TERMS)
        raise KeyError(f"history has no energy column (expected some of: {expected})")

    figure = Figure(figsize=(7.0, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    for name in terms:
        style = {"color": "black", "linewidth": 2.0} if name == "total" else {}
        axes.plot(time, _column(history, name), label=ENERGY_TERMS[name], **style)
    axes.set_xlabel("time [s]")
    axes.set_ylabel("energy [J; J/m in 2D]")
    axes.grid(True, alpha=0.3)
    axes.legend()
    if title:
        axes.set_title(title)

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=120)
    return path
