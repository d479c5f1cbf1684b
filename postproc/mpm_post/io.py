"""Readers for the files mpm-geo writes into a run directory (outputs/<case>/).

particles_NNNNNN.h5
    root attributes ``time`` [s], ``step``, ``dimension``, ``case_name``;
    group ``/particles``: ``position`` (n, 3) [m] (z = 0 in 2D) and optionally ``displacement``
    (n, 3) [m], ``velocity`` (n, 3) [m/s], ``stress`` and ``strain`` (n, 4 in 2D: xx yy zz xy;
    n, 6 in 3D: xx yy zz xy yz zx; tension positive) [Pa, -], ``material`` (n), ``mass`` (n) [kg],
    ``volume`` (n) [m^3]; in cases with ``pore_water`` also ``pore_pressure`` (n) [Pa,
    compression positive], ``eff_stress`` (as stress) [Pa] and ``water_velocity`` (n, 3) [m/s];
    optional group ``/grid`` with ``position``, ``mass``, ``velocity``.
history.csv
    header ``time,step,kinetic_energy,elastic_energy,potential_energy,plastic_work,viscous_work,
    damping_work,friction_work,load_work,boundary_work,transfer_loss,total,residual`` (without
    the boundary and transfer terms before issue 19, item 5; before issue 19:
    ``time,step,kinetic_energy,strain_energy,potential_energy,damping_work,total``).
terrain.h5 (runs with a terrain_stl contact)
    ``/terrain/position`` (3 n, 3) [m], the 3 corners of each of the n triangles, and
    ``/terrain/triangles`` (3 n), their 0-based indices.
"""

import re
import warnings
from pathlib import Path

import h5py
import numpy as np

OUTPUT_PATTERN = re.compile(r"particles_(\d{6})\.h5")
HISTORY_FILE = "history.csv"
TERRAIN_FILE = "terrain.h5"
# Column labels of the particle fields (docs/output.md): Voigt order for stress and strain.
STRESS_COMPONENTS = {4: ["xx", "yy", "zz", "xy"], 6: ["xx", "yy", "zz", "xy", "yz", "zx"]}
VECTOR_COMPONENTS = ["x", "y", "z"]
# A requested time this close to the span of the outputs, relative to the largest output time,
# is inside it: an output is written at the first step at or after its time.
TIME_TOLERANCE = 1.0e-3


class TimeOutsideRunError(ValueError):
    """A requested time before the first or after the last output of a run.

    A ValueError, so callers that catch those keep working; the command line turns it into exit
    code 2 (bad input) rather than answering with the nearest output, the first or the last,
    which describes another time than the one asked for.
    """


def component_names(name, array):
    """Labels of the columns of the particle field ``name``, an array as load_particles gives.

    ``[name]`` for one value per particle, ``x y z`` for vectors, the Voigt labels for
    ``stress`` and ``strain``, column numbers otherwise.
    """
    if array.ndim == 1:
        return [name]
    ncol = array.shape[1]
    if name in ("stress", "strain") and ncol in STRESS_COMPONENTS:
        return list(STRESS_COMPONENTS[ncol])
    if ncol == 3:
        return list(VECTOR_COMPONENTS)
    return [str(i) for i in range(ncol)]


def _run_dir(run_dir):
    """The run directory as a Path, or a clear error when it is not one."""
    path = Path(run_dir)
    if not path.exists():
        raise FileNotFoundError(f"run directory not found: {path}")
    if not path.is_dir():
        raise NotADirectoryError(f"not a run directory: {path}")
    return path


def _scalar(value):
    """An HDF5 attribute as a Python scalar (Fortran writers often store 1-element arrays)."""
    array = np.asarray(value)
    if array.size != 1:
        raise ValueError(f"expected a single value, got shape {array.shape}")
    item = array.reshape(-1)[0]
    if isinstance(item, (bytes, np.bytes_)):
        item = item.decode("utf-8", errors="replace")
    if isinstance(item, str):
        return item.rstrip("\0 ")
    return item.item() if hasattr(item, "item") else item


def _attribute(h5file, name, path, default=None):
    if name not in h5file.attrs:
        if default is not None:
            return default
        raise ValueError(f"{path}: root attribute '{name}' is missing")
    try:
        return _scalar(h5file.attrs[name])
    except ValueError as exc:
        raise ValueError(f"{path}: attribute '{name}': {exc}") from None


def _output_time(path):
    with h5py.File(path, "r") as h5file:
        return float(_attribute(h5file, "time", path))


def list_outputs(run_dir):
    """Particle outputs of a run, sorted by time.

    Returns a list of ``(time, path)`` with time [s] read from each file's ``time`` attribute;
    an empty list when the directory holds no ``particles_NNNNNN.h5`` file.
    Raises FileNotFoundError / NotADirectoryError when ``run_dir`` is not a directory.
    """
    directory = _run_dir(run_dir)
    files = [p for p in directory.iterdir() if p.is_file() and OUTPUT_PATTERN.fullmatch(p.name)]
    return sorted((_output_time(p), p) for p in files)


def _times_text(times):
    """Output times [s] for a message: all of them, or the first and last six."""
    if len(times) <= 12:
        return " ".join(f"{t:g}" for t in times)
    return " ".join(f"{t:g}" for t in times[:6]) + " ... " + \
        " ".join(f"{t:g}" for t in times[-6:])


def _check_span(times, time, path):
    """Raise TimeOutsideRunError when ``time`` [s] lies outside the output ``times`` [s].

    Within TIME_TOLERANCE of the largest output time of either end counts as inside.
    """
    time = float(time)
    margin = TIME_TOLERANCE * float(np.max(np.abs(times)))
    if not np.isfinite(time):
        raise TimeOutsideRunError(f"time must be a finite number of seconds, got {time:g}")
    if times[0] - margin <= time <= times[-1] + margin:
        return
    side = "after the last" if time > times[-1] else "before the first"
    raise TimeOutsideRunError(
        f"no output at time {time:g} s in {path}: it is {side} output (the outputs run from "
        f"{times[0]:g} to {times[-1]:g} s; output times [s]: {_times_text(times)})")


def _select_output(path_or_run_dir, time):
    """The output file to read: the file itself, or the run's output nearest to ``time``.

    Raises TimeOutsideRunError when ``time`` is outside the span of the outputs.
    """
    path = Path(path_or_run_dir)
    if path.is_file():
        if time is not None:
            raise ValueError(f"time={time} selects an output of a run directory, not of a file")
        return path
    outputs = list_outputs(path)
    if not outputs:
        raise FileNotFoundError(f"no particles_NNNNNN.h5 output in {path}")
    if time is None:
        return outputs[-1][1]
    times = np.array([t for t, _ in outputs])
    _check_span(times, time, path)
    return outputs[int(np.argmin(np.abs(times - float(time))))][1]


def output_at(path_or_run_dir, time=None, tolerance=None):
    """The output file at ``time`` [s]: the last one when None, else one within ``tolerance``.

    Unlike load_particles, which takes the nearest output, this refuses a time that no output
    is close to: for a comparison with an exact solution at that time. ``tolerance`` [s]
    defaults to 1e-3 of the last output time, enough for an output written at the first time
    step at or after the requested time. ``path_or_run_dir``: a run directory or one
    ``particles_NNNNNN.h5`` file. Returns ``(time, path)`` of the output; raises ValueError
    naming the output times when none is within the tolerance, TimeOutsideRunError (a
    ValueError) when ``time`` lies before the first or after the last output.
    """
    path = Path(path_or_run_dir)
    outputs = [(_output_time(path), path)] if path.is_file() else list_outputs(path)
    if not outputs:
        raise FileNotFoundError(f"no particles_NNNNNN.h5 output in {path}")
    if time is None:
        return outputs[-1]
    times = np.array([t for t, _ in outputs])
    if tolerance is None:
        tolerance = TIME_TOLERANCE * float(np.max(np.abs(times)))
    nearest = int(np.argmin(np.abs(times - float(time))))
    if not abs(times[nearest] - float(time)) <= tolerance:
        if len(outputs) > 1:
            _check_span(times, time, path)
        raise ValueError(f"no output at time {time:g} s in {path} (output times [s]: "
                         f"{_times_text(times)}; tolerance {tolerance:g} s)")
    return outputs[nearest]


def _read_header(h5file, path):
    return {
        "time": float(_attribute(h5file, "time", path)),
        "step": int(_attribute(h5file, "step", path)),
        "dimension": int(_attribute(h5file, "dimension", path, default=0)),
        "case_name": str(_attribute(h5file, "case_name", path, default="")),
        "path": str(path),
    }


def _read_group(h5file, group_name, path):
    """All datasets of a group as arrays, checked to have one row per point."""
    group = h5file[group_name]
    if "position" not in group:
        raise ValueError(f"{path}: dataset /{group_name}/position is missing")
    position = np.asarray(group["position"][()], dtype=float)
    if position.ndim != 2 or position.shape[1] != 3:
        raise ValueError(f"{path}: /{group_name}/position has shape {position.shape}, "
                         "expected (n, 3)")
    n = position.shape[0]
    data = {"position": position}
    for name, dataset in group.items():
        if name == "position" or not isinstance(dataset, h5py.Dataset):
            continue
        array = np.asarray(dataset[()])
        if array.ndim == 0 or array.shape[0] != n:
            raise ValueError(f"{path}: /{group_name}/{name} has shape {array.shape}, "
                             f"expected {n} rows like position")
        data[name] = array
    return data


def load_particles(path_or_run_dir, time=None):
    """Particle data of one output.

    ``path_or_run_dir`` is a ``particles_NNNNNN.h5`` file or a run directory; in a run directory
    the output nearest to ``time`` [s] is read (the last one when ``time`` is None); a ``time``
    before the first or after the last output raises TimeOutsideRunError (a ValueError) naming
    the output times, rather than silently reading the first or the last.
    Returns a dict with one numpy array per dataset of ``/particles`` (``position`` always, the
    others when written) and ``time`` [s], ``step``, ``dimension``, ``case_name``, ``path``.
    """
    path = _select_output(path_or_run_dir, time)
    with h5py.File(path, "r") as h5file:
        if "particles" not in h5file:
            raise ValueError(f"{path}: group /particles is missing")
        data = _read_group(h5file, "particles", path)
        data.update(_read_header(h5file, path))
    return data


def load_grid(path_or_run_dir, time=None):
    """Grid data of one output (selected as in load_particles), or None when none was written."""
    path = _select_output(path_or_run_dir, time)
    with h5py.File(path, "r") as h5file:
        if "grid" not in h5file:
            return None
        data = _read_group(h5file, "grid", path)
        data.update(_read_header(h5file, path))
    return data


def load_history(run_dir):
    """The energy history of a run (``history.csv`` in ``run_dir``, or the CSV file itself).

    Returns a dict of 1-D arrays, one per column (``time`` [s], ``step``, the energies [J]);
    the arrays are empty when the run has written only the header.
    """
    path = Path(run_dir)
    if path.is_dir():
        path = path / HISTORY_FILE
    if not path.is_file():
        raise FileNotFoundError(f"history file not found: {path}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numpy warns on a header-only file
        try:
            table = np.genfromtxt(path, delimiter=",", names=True, dtype=float, ndmin=1)
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None
    if table.dtype.names is None:
        raise ValueError(f"{path}: no header line")
    if "time" not in table.dtype.names:
        raise ValueError(f"{path}: no 'time' column (columns: {', '.join(table.dtype.names)})")
    return {name: np.asarray(table[name], dtype=float) for name in table.dtype.names}


def load_terrain(run_dir):
    """The terrain surface of a run, or None when it has none (no ``terrain.h5``).

    ``run_dir``: a run directory, or a file in one (a ``particles_NNNNNN.h5``). Returns the
    corners of the triangles as an (n, 3, 3) array [m]: triangle, corner, x y z.
    """
    path = Path(run_dir)
    folder = path if path.is_dir() else path.parent
    path = folder / TERRAIN_FILE
    if not path.is_file():
        return None
    with h5py.File(path, "r") as h5file:
        for name in ("position", "triangles"):
            if f"terrain/{name}" not in h5file:
                raise ValueError(f"{path}: dataset /terrain/{name} is missing")
        position = np.asarray(h5file["terrain/position"][()], dtype=float)
        triangles = np.asarray(h5file["terrain/triangles"][()], dtype=np.int64).reshape(-1)
    if position.ndim != 2 or position.shape[1] != 3 or triangles.size % 3 != 0 or \
            np.any(triangles < 0) or np.any(triangles >= position.shape[0]):
        raise ValueError(f"{path}: /terrain/position {position.shape} and /terrain/triangles "
                         f"({triangles.size}) do not describe triangles")
    return position[triangles].reshape(-1, 3, 3)
