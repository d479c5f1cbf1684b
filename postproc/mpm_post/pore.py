"""Pore pressure of saturated soils (cases with ``pore_water``): ``mpm_post pore``.

Each output of such a case holds ``/particles/pore_pressure`` (n) [Pa, compression positive]
(docs/output.md), next to ``eff_stress`` and ``water_velocity``. ``load_pore_pressure`` reads
the pore pressure and the heights of the particles at every output of a run,
``profile_by_height`` averages a profile per height, ``nearest_particles`` picks the particles
to follow in time and ``plot_pore_pressure`` draws the figure of the command: the profiles
(isochrones of a consolidation) and the pressure of a few particles against time.

The particles are followed by their index (their row in ``/particles``): the order of the
particles is the same in every output of one run on one image.
"""

from pathlib import Path
from typing import NamedTuple

import h5py
import numpy as np

from .io import _attribute, list_outputs

PORE_FIELD = "pore_pressure"
AXES = {"y": 1, "z": 2}
# Heights closer than this [m] are one height of a profile (profile_by_height).
HEIGHT_ROUNDING = 1.0e-9
# Default heights to follow, as fractions of the particles' vertical extent at the first output.
DEFAULT_FRACTIONS = (0.25, 0.5, 0.75)


class PoreInputError(ValueError):
    """The run cannot give a pore pressure: no such folder, no output, or an output without
    ``pore_pressure`` (a case without ``pore_water``, or one whose ``output.fields`` leaves it
    out), or a vertical axis the positions do not have. The command line exits with code 2."""


class PoreHistory(NamedTuple):
    """Pore pressure and heights of the particles of a run at each of its outputs.

    ``time`` (m,) [s], sorted; ``height`` and ``pressure`` (m, n): the vertical coordinate [m]
    and the pore pressure [Pa, compression positive] of particle j (its row in the files) at
    output i; ``axis``: the name of the vertical (``y`` or ``z``); ``paths``: the m files.
    """

    time: np.ndarray
    height: np.ndarray
    pressure: np.ndarray
    axis: str
    paths: list
    case_name: str
    dimension: int


def vertical_axis(dimension, position, requested=None):
    """(name, column) of the vertical coordinate of ``position`` (n, 2 or 3).

    ``requested``: ``y`` or ``z``, or None for y in 2D and z in 3D (``dimension``); when the
    dimension is not known (0), the last coordinate of the positions, or y when the positions
    have a z column that is 0 everywhere (a 2D run writes z = 0).
    Raises PoreInputError for z in a 2D run or positions without a z column.
    """
    ncol = position.shape[1]
    if requested is None:
        if dimension == 3 or (dimension != 2 and ncol == 3 and np.any(position[:, 2] != 0.0)):
            requested = "z"
        else:
            requested = "y"
    column = AXES[requested]
    if column >= ncol or (requested == "z" and dimension == 2):
        raise PoreInputError(f"--vertical-axis {requested}: the run is 2D (positions x y), its "
                             "vertical is y")
    return requested, column


def _read_output(path, n):
    """(dimension, case name, position, pore pressure) of one output; n: the particle count
    of the first output (None for the first)."""
    with h5py.File(path, "r") as h5file:
        if "particles" not in h5file:
            raise ValueError(f"{path}: group /particles is missing")
        group = h5file["particles"]
        if PORE_FIELD not in group:
            raise PoreInputError(f"{path} has no {PORE_FIELD}: the case has no pore_water "
                                 f"(list {PORE_FIELD} in output.fields)")
        if "position" not in group:
            raise ValueError(f"{path}: dataset /particles/position is missing")
        position = np.asarray(group["position"][()], dtype=float)
        pressure = np.asarray(group[PORE_FIELD][()], dtype=float).reshape(-1)
        dimension = int(_attribute(h5file, "dimension", path, default=0))
        case_name = str(_attribute(h5file, "case_name", path, default=""))
    if position.ndim != 2 or position.shape[1] not in (2, 3):
        raise ValueError(f"{path}: /particles/position has shape {position.shape}, expected "
                         "(n, 2) or (n, 3)")
    if pressure.size != position.shape[0]:
        raise ValueError(f"{path}: /particles/{PORE_FIELD} has {pressure.size} values for "
                         f"{position.shape[0]} particles")
    if n is not None and pressure.size != n:
        raise ValueError(f"{path} holds {pressure.size} particles, the first output {n}: the "
                         "particles cannot be followed by their index")
    return dimension, case_name, position, pressure


def load_pore_pressure(run_dir, axis=None):
    """The PoreHistory of the run directory ``run_dir`` (every ``particles_NNNNNN.h5``).

    ``axis``: ``y``, ``z`` or None (vertical_axis). Raises PoreInputError when the folder does
    not exist or holds no output, or when an output has no ``pore_pressure``; ValueError when
    the outputs do not hold the same particles.
    """
    try:
        outputs = list_outputs(run_dir)
    except (FileNotFoundError, NotADirectoryError) as exc:
        raise PoreInputError(str(exc)) from None
    if not outputs:
        raise PoreInputError(f"no particles_NNNNNN.h5 output in {run_dir}")
    times, heights, pressures, column = [], [], [], None
    dimension = case_name = None
    for time, path in outputs:
        dim, case, position, pressure = _read_output(path, None if column is None
                                                     else pressures[0].size)
        if column is None:
            dimension, case_name = dim, case
            axis, column = vertical_axis(dim, position, axis)
        elif position.shape[1] <= column:
            raise ValueError(f"{path}: /particles/position has shape {position.shape}, the "
                             f"first output ({outputs[0][1]}) has a {axis} column")
        times.append(time)
        heights.append(position[:, column])
        pressures.append(pressure)
    return PoreHistory(np.array(times), np.array(heights), np.array(pressures), axis,
                       [path for _, path in outputs], case_name or Path(run_dir).name,
                       dimension)


def default_heights(height, fractions=DEFAULT_FRACTIONS):
    """Heights [m] at ``fractions`` of the vertical extent of the particle heights ``height``."""
    low, high = float(np.min(height)), float(np.max(height))
    return [low + f * (high - low) for f in fractions]


def nearest_particles(height, targets):
    """Index of the particle of ``height`` (n,) nearest to each of ``targets`` [m]; the first
    in file order when several are as near."""
    height = np.asarray(height, dtype=float)
    return [int(np.argmin(np.abs(height - float(target)))) for target in targets]


def profile_by_height(height, pressure):
    """(heights, mean pressures) of one output: the particles whose heights agree to
    HEIGHT_ROUNDING [m] averaged into one point, sorted by height."""
    keys, inverse = np.unique(np.round(np.asarray(height, dtype=float) / HEIGHT_ROUNDING),
                              return_inverse=True)
    inverse = inverse.reshape(-1)
    count = np.bincount(inverse, minlength=keys.size)
    mean_height = np.bincount(inverse, weights=height, minlength=keys.size) / count
    mean_pressure = np.bincount(inverse, weights=pressure, minlength=keys.size) / count
    return mean_height, mean_pressure


def plot_pore_pressure(path, history, particles, targets, title=None):
    """The figure of ``mpm_post pore``; returns the Path of the image.

    Left: pore pressure [kPa] against height at every output (profile_by_height), coloured by
    time (colorbar). Right: the pore pressure [kPa] of the particles of index ``particles``
    against time, labelled with the heights ``targets`` [m] they were picked at.
    """
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    from .plots import _figure, _save

    figure = _figure(width=11.0, height=4.8)
    profiles, series = figure.subplots(1, 2)
    times = history.time
    norm = Normalize(float(times[0]), float(times[-1]) if times[-1] > times[0]
                     else float(times[0]) + 1.0)
    cmap = colormaps["viridis"]
    marker = "." if history.height.shape[1] <= 200 else None
    for time, height, pressure in zip(times, history.height, history.pressure):
        h, p = profile_by_height(height, pressure)
        profiles.plot(p / 1.0e3, h, color=cmap(norm(time)), marker=marker, markersize=3,
                      linewidth=1.2)
    figure.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=profiles, label="time [s]")
    profiles.set_xlabel("pore pressure [kPa]")
    profiles.set_ylabel(f"{history.axis} [m]")
    profiles.set_title(f"profiles at {times.size} outputs (mean per height)")
    profiles.grid(True, alpha=0.3)

    many = times.size > 40
    for k, (index, target) in enumerate(zip(particles, targets)):
        colour = f"C{k % 10}"
        series.plot(times, history.pressure[:, index] / 1.0e3, color=colour,
                    marker=None if many else ".",
                    label=f"{history.axis} = {target:.4g} m (particle {index})")
        profiles.axhline(history.height[0, index], color=colour, linestyle=":", linewidth=1.0)
    series.set_xlabel("time [s]")
    series.set_ylabel("pore pressure [kPa]")
    series.set_title("particles nearest to these heights at the first output")
    series.grid(True, alpha=0.3)
    if particles:
        series.legend(fontsize="small")
    if title:
        figure.suptitle(title)
    return _save(figure, path)
