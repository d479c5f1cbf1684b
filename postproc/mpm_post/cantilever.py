"""The cantilever under sudden gravity of Sadeghirad et al. (2011), REFERENCES.md section 8.

Shared by the study (bench/study_cantilever.py) and the validation case
(validation/cantilever/check.py):

- ``cantilever_case``: the case file (a dict) of one run;
- ``measure``: the peak deflection of the free end and the energy residual of a run's outputs;
- ``richardson`` (from mpm_post.study): the discretisation error of a ladder of refinements
  (observed order, extrapolated value, Roache's grid convergence index);
- ``peak_bands``: the pass bands of the peaks and of the energy residuals derived from the
  spread of the published peaks and the discretisation error of the ladder.

The beam: 4 m x 1 m, clamped at x = 0 (the beam starts on the domain face xmin, boundary
``fixed``), neo-Hookean E = 1 MPa, nu = 0.3, rho = 1050 kg/m3, gravity 10 m/s2 from t = 0,
plane strain, no damping, CFL 0.5; domain 4.5 m x 5.5 m with the beam at y = 4..5 (the other
faces free and out of reach).
"""

import numpy as np

from .io import list_outputs, load_history, load_particles
from .study import Richardson, richardson  # noqa: F401 (part of this module's interface)

PUBLISHED_PEAK = 3.31     # [m] Sadeghirad et al. (2011), CPDI
PUBLISHED_PEAK_CPGIMP = 3.32  # [m] the same paper, cpGIMP
CORNER = (4.0, 4.0)       # [m] bottom corner of the free end


def case_name(dx, shape, scheme, transfer, ppc):
    """The name of one run's case (no dot, so that it is a file stem)."""
    return f"cantilever_{dx:g}_{shape}_{scheme}_{transfer}_{ppc}".replace(".", "p")


def cantilever_case(dx, shape, scheme, transfer, ppc, tend=3.0, interval=0.01):
    """The case file (a dict) of one run.

    ``dx`` the cell size [m], ``shape`` solver.shape_function, ``scheme`` solver.scheme,
    ``transfer`` solver.transfer (``xpicM``: "xpic" with solver.xpic_order M), ``ppc``
    particles per cell and axis, ``tend`` the simulated time [s], ``interval`` the output
    interval [s] (the peak is read at the output times).
    """
    solver = {"scheme": scheme, "shape_function": shape, "transfer": transfer}
    if transfer.startswith("xpic") and transfer[4:].isdigit():
        solver.update(transfer="xpic", xpic_order=int(transfer[4:]))
    return {
        "name": case_name(dx, shape, scheme, transfer, ppc),
        "domain": {"nx": round(4.5 / dx), "ny": round(5.5 / dx), "dx": dx,
                   "origin": [0.0, 0.0],
                   "boundaries": {"xmin": "fixed", "xmax": "free", "ymin": "free",
                                  "ymax": "free"}},
        "particles": {"ppc": ppc, "distribution": "regular"},
        "materials": [{"name": "beam", "type": "neo_hookean", "E": 1.0e6, "nu": 0.3,
                       "rho": 1050.0}],
        "bodies": [{"name": "beam", "material": "beam", "min": [0.0, 4.0], "max": [4.0, 5.0]}],
        "gravity": [0.0, -10.0],
        "solver": solver,
        "time": {"tend": tend, "cfl": 0.5},
        "damping": {"type": "none"},
        "output": {"interval": interval, "fields": ["position", "displacement"]},
    }


def measure(output):
    """The measures of one run from its output folder ``output``.

    - ``peak_m``: the largest downward displacement of the particle of the free end nearest
      the bottom corner (4, 4) (the particles keep their order on one image), over the output
      times, and ``peak_time_s`` when it happened;
    - ``residual_rel``: the ``residual`` of history.csv at the end of the run over the largest
      drop of the potential energy, and ``residual_at_peak_rel`` the same at the history line
      nearest the peak;
    - ``particles``, ``end_s`` (the time reached), ``times_s`` and ``tip_deflection_m`` (the
      deflection at every output time, for plots).
    Raises OSError, KeyError, IndexError or ValueError when the outputs are missing or broken.
    """
    outputs = list_outputs(output)
    first = load_particles(outputs[0][1])
    start = first["position"] - first["displacement"]
    tip = int(np.argmin(np.hypot(start[:, 0] - CORNER[0], start[:, 1] - CORNER[1])))
    times, deflection = [], []
    for time, path in outputs:
        times.append(float(time))
        deflection.append(-float(load_particles(path)["displacement"][tip, 1]))
    deflection = np.asarray(deflection)
    peak_index = int(np.argmax(deflection))
    history = load_history(output)
    potential = history["potential_energy"]
    drop = float(np.max(potential[0] - potential))
    at_peak = int(np.argmin(np.abs(history["time"] - times[peak_index])))
    return {
        "particles": int(len(start)),
        "peak_m": float(deflection[peak_index]),
        "peak_time_s": times[peak_index],
        "residual_rel": float(history["residual"][-1]) / drop,
        "residual_at_peak_rel": float(history["residual"][at_peak]) / drop,
        "end_s": float(history["time"][-1]),
        "times_s": times,
        "tip_deflection_m": deflection.tolist(),
    }


def peak_bands(peaks, ratio=2.0, reference=PUBLISHED_PEAK,
               other_reference=PUBLISHED_PEAK_CPGIMP):
    """The pass bands of a ladder of peaks (coarse to fine) [m], derived, not picked.

    Uncertainty of the reference: the spread of the published values, |3.32 - 3.31| m (CPDI
    against cpGIMP in the same paper, each at its own resolution). Discretisation error of a
    rung: safety x |peak - extrapolated| (``richardson``). The peak of a rung passes when
    |peak - reference| <= spread + safety x its error, the extrapolated peak when
    |extrapolated - reference| <= spread + GCI of the finest rung.

    The energy residual gets the same band, relative: under a sudden load a linear spring
    peaks at u = 2 m g / k; an energy e (a fraction of the drop of the potential energy) lost or
    gained before the peak moves it by the same fraction e, so a residual inside the relative
    peak band cannot be told from the uncertainty of the peak.

    Returns a dict: ``spread_m``, ``richardson`` (a Richardson), ``peak_band_m`` (one per rung),
    ``residual_band`` (one per rung, a fraction), ``extrapolated_band_m``.
    """
    spread = abs(other_reference - reference)
    fit = richardson(peaks, ratio)
    peak_band = [spread + fit.safety * e for e in fit.errors]
    return {
        "spread_m": spread,
        "richardson": fit,
        "peak_band_m": peak_band,
        "residual_band": [b / reference for b in peak_band],
        "extrapolated_band_m": spread + fit.gci_fine,
    }
