"""The cantilever under sudden gravity of Sadeghirad et al. (2011), REFERENCES.md section 8.

Shared by the study (bench/study_cantilever.py) and the validation case
(validation/cantilever/check.py):

- ``cantilever_case``: the case file (a dict) of one run;
- ``measure``: the peak deflection of the free end and the energy residual of a run's outputs;
- ``richardson``: the discretisation error of a ladder of refinements (observed order,
  extrapolated value, Roache's grid convergence index);
- ``peak_bands``: the pass bands of the peaks and of the energy residuals derived from the
  spread of the published peaks and the discretisation error of the ladder.

The beam: 4 m x 1 m, clamped at x = 0 (the beam starts on the domain face xmin, boundary
``fixed``), neo-Hookean E = 1 MPa, nu = 0.3, rho = 1050 kg/m3, gravity 10 m/s2 from t = 0,
plane strain, no damping, CFL 0.5; domain 4.5 m x 5.5 m with the beam at y = 4..5 (the other
faces free and out of reach).
"""

import math
from typing import NamedTuple

import numpy as np

from .io import list_outputs, load_history, load_particles

PUBLISHED_PEAK = 3.31     # [m] Sadeghirad et al. (2011), CPDI
PUBLISHED_PEAK_CPGIMP = 3.32  # [m] the same paper, cpGIMP
CORNER = (4.0, 4.0)       # [m] bottom corner of the free end
SAFETY_FACTOR_THREE = 1.25  # Roache's factor of safety with three grids and an observed order
SAFETY_FACTOR_TWO = 3.0     # and without one (two grids, or a ladder that is not monotone)


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
