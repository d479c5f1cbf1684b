"""Energy balance of a run, from the dict returned by load_history (history.csv).

One definition of the energy drift (energy_balance, describe_drift) and one energy figure
(plot_run_energy) for every command that shows them: ``summary``, ``energy``, ``plot energy``.
"""

from pathlib import Path
from typing import NamedTuple

import numpy as np

from .io import list_outputs, load_history, load_particles

# Columns of history.csv [J] (per unit thickness in 2D) and their labels in plots.
ENERGY_TERMS = {
    "kinetic_energy": "kinetic",
    "elastic_energy": "elastic (stored)",
    "strain_energy": "strain",
    "potential_energy": "potential",
    "plastic_work": "plastic dissipation",
    "viscous_work": "viscous dissipation (fluids, pore-water flow)",
    "damping_work": "damping work",
    "friction_work": "friction work",
    "load_work": "work of loads",
    "boundary_work": "stopped by fixed faces and contacts",
    "transfer_loss": "lost in particle-grid transfers",
    "total": "total",
    "residual": "residual",
}

# Where the energy of a run went (docs/output.md): stacked in plots of a history with a
# ``residual`` column, against the energy the run was given.
STACKED_TERMS = ("kinetic_energy", "elastic_energy", "plastic_work", "viscous_work",
                 "damping_work", "friction_work", "boundary_work", "transfer_loss")


# Columns of history.csv that are not energies.
NOT_ENERGY = ("time", "step")


def energy_columns(history):
    """(column, label) of the energy terms of a history to plot, in the header's names.

    The known terms (ENERGY_TERMS) first in that order, then any other column of the header
    but time and step under its own name, so that a term added to history.csv is shown too.
    """
    known = [(name, label) for name, label in ENERGY_TERMS.items() if name in history]
    other = [(name, name.replace("_", " ")) for name in history
             if name not in ENERGY_TERMS and name not in NOT_ENERGY]
    return known + other


def _column(history, name):
    if name not in history:
        raise KeyError(f"history has no '{name}' column (columns: {', '.join(history)})")
    return np.asarray(history[name], dtype=float)


class EnergyBalance(NamedTuple):
    """The energy balance of a run between its first and its last history line.

    ``drift`` [J]: total at the end - total at the start, the energy the run does not account
    for (0 for an exactly conserving run; > 0 energy was created). ``gravity_work`` [J]: the
    work of gravity over the run, potential energy at the start - at the end (nan without a
    ``potential_energy`` column). ``start``, ``end`` [s]: the times of the two lines.
    ``load_work`` [J]: the work of the loads over the run (0 without a ``load_work`` column).
    All energies per metre of thickness [J/m] in 2D.
    """

    drift: float
    gravity_work: float
    start: float
    end: float
    load_work: float = 0.0

    @property
    def supplied(self):
        """The work given to the material: of gravity (when known) and of the loads [J]."""
        if np.isnan(self.gravity_work):
            return self.load_work if self.load_work != 0.0 else float("nan")
        return self.gravity_work + self.load_work

    @property
    def supplied_name(self):
        """What `supplied` is made of, in words."""
        if self.load_work == 0.0:
            return "the work of gravity"
        if np.isnan(self.gravity_work) or self.gravity_work == 0.0:
            return "the work of the loads"
        return "the work of gravity and loads"

    @property
    def drift_of_gravity_work(self):
        """drift / supplied (the work of gravity and of the loads) [-], nan when they did no
        positive work."""
        if not self.supplied > 0.0:
            return float("nan")
        return self.drift / self.supplied


def energy_balance(history):
    """The EnergyBalance of a history (the dict of load_history).

    The columns are found by their names in the header (``time``, ``total``,
    ``potential_energy``), wherever they stand; ``potential_energy`` may be missing.
    """
    total = _column(history, "total")
    time = _column(history, "time")
    if total.size == 0:
        raise ValueError("history is empty: no energy drift to compute")
    work = float("nan")
    if "potential_energy" in history:
        potential = _column(history, "potential_energy")
        work = float(potential[0] - potential[-1])
    loads = 0.0
    if "load_work" in history:
        load_work = _column(history, "load_work")
        loads = float(load_work[-1] - load_work[0])
    return EnergyBalance(float(total[-1] - total[0]), work, float(time[0]), float(time[-1]),
                         loads)


DRIFT_DEFINITION = "total at the end - total at the start: energy not accounted for"


def energy_unit(dimension):
    """Unit of the energies of history.csv for a run of that dimension (0: not known)."""
    return {2: "J/m", 3: "J"}.get(dimension, "J (J/m in 2D)")


def describe_drift(balance, unit="J"):
    """The drift of an EnergyBalance in words: value, unit, definition, share of gravity work.

    For example ``+1.27 J (total at the end - total at the start: energy not accounted for;
    3.2 % of the work of gravity, 39.7 J)``.
    """
    share = balance.drift_of_gravity_work
    if np.isfinite(share):
        compared = (f"{100.0 * share:.3g} % of {balance.supplied_name}, "
                    f"{balance.supplied:.3g} {unit}")
    elif np.isnan(balance.supplied):
        compared = "no potential_energy column to compare with the work of gravity"
    else:
        compared = (f"{balance.supplied_name} is {balance.supplied:.3g} {unit}, not "
                    "positive")
    return f"{balance.drift:+.3g} {unit} ({DRIFT_DEFINITION}; {compared})"


def _run_of(run):
    """(case name, dimension) of the run directory of ``run`` (a folder or its history.csv),
    from its last particle output; (folder name, 0) when it has none."""
    folder = Path(run)
    folder = folder if folder.is_dir() else folder.parent
    outputs = list_outputs(folder)
    if outputs:
        last = load_particles(outputs[-1][1])
        return last["case_name"] or folder.name, last["dimension"]
    return folder.name, 0


def plot_run_energy(run, path):
    """The energy figure of a run: its history.csv plotted, titled with the case and the drift.

    ``run``: a run directory or its history.csv. What ``mpm_post energy`` and ``mpm_post plot
    energy`` write. Returns ``(path, drift)``: the image's Path and the drift in words
    (describe_drift), or None when the history has no ``total`` column.
    """
    history = load_history(run)
    if history["time"].size == 0:
        raise ValueError(f"history of {run} is empty: nothing to plot")
    case, dimension = _run_of(run)
    unit = energy_unit(dimension)
    title = case
    drift = None
    if "total" in history:
        balance = energy_balance(history)
        drift = describe_drift(balance, unit)
        title += (f"\nenergy drift {balance.drift:+.3g} {unit} = total at t = {balance.end:g} s "
                  f"- total at t = {balance.start:g} s")
        share = balance.drift_of_gravity_work
        if np.isfinite(share):
            title += (f"\n({100.0 * share:.3g} % of {balance.supplied_name}, "
                      f"{balance.supplied:.3g} {unit})")
    return plot_energy(history, path, title=title, unit=unit), drift


def plot_energy(history, path, title=None, unit="J; J/m in 2D"):
    """Plot every energy term of ``history`` against time into an image file; returns its Path.

    ``title``: an optional title of the plot (the run, its energy drift, ...); ``unit``: of the
    energy axis. The total at the start is a dashed line: the total's distance from it is the
    drift (energy_balance).

    Uses matplotlib's Agg canvas directly, so no display is needed and the global backend of a
    calling program is left alone. The parent directory is created when missing.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    time = _column(history, "time")
    if "residual" in history and "potential_energy" in history:
        return _plot_stacked(history, time, path, title, unit)
    terms = energy_columns(history)
    if not terms:
        expected = ", ".join(ENERGY_TERMS)
        raise KeyError(f"history has no energy column (expected some of: {expected})")

    figure = Figure(figsize=(7.0, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    for name, label in terms:
        style = {"color": "black", "linewidth": 2.0} if name == "total" else {}
        axes.plot(time, _column(history, name), label=label, **style)
    axes.set_xlabel("time [s]")
    if "total" in history:
        total = _column(history, "total")
        axes.axhline(total[0], color="0.4", linestyle="--", linewidth=1.0,
                     label=f"total at t = {time[0]:g} s")
    axes.set_ylabel(f"energy [{unit}]")
    axes.grid(True, alpha=0.3)
    axes.legend()
    if title:
        axes.set_title(title)

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=120)
    return path


def _plot_stacked(history, time, path, title, unit):
    """plot_energy of a history with the closed balance (``residual`` column): the terms of
    STACKED_TERMS stacked, the energy given to the run (initial kinetic + elastic energy,
    work of gravity = - potential energy, work of loads) as a line, and the residual, the
    energy the discretisation created (> 0) or lost (< 0), as a line of its own."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7.0, 4.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    names = [name for name in STACKED_TERMS if name in history]
    axes.stackplot(time, *[_column(history, name) for name in names],
                   labels=[ENERGY_TERMS[name] for name in names], alpha=0.8)
    given = _column(history, "total")[0] - _column(history, "potential_energy")
    if "load_work" in history:
        given = given + _column(history, "load_work")
    axes.plot(time, given, color="black", linewidth=2.0,
              label="given: initial + work of gravity and loads")
    axes.plot(time, _column(history, "residual"), color="red", linewidth=1.5,
              label="residual (created > 0, lost < 0)")
    axes.axhline(0.0, color="0.4", linewidth=0.8)
    axes.set_xlabel("time [s]")
    axes.set_ylabel(f"energy [{unit}]")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize="small")
    if title:
        axes.set_title(title)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=120)
    return path
