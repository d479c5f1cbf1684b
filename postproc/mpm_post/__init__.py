"""Read and summarise the outputs of mpm-geo runs.

A run directory (``outputs/<case>/``) holds ``particles_NNNNNN.h5`` files, one per output time,
a ``<case>.xdmf`` index for ParaView and ``history.csv`` with the energy balance.
Layout: docs/output.md; the command line and the modules: docs/postproc.md.
Figures (matplotlib) are in ``mpm_post.plots``, study tools in ``mpm_post.study`` and the helpers
shared by the validation scripts (validation/<case>/check.py) in ``mpm_post.validation``:
imported on demand, so that reading outputs does not load matplotlib.
"""

from .energy import describe_drift, energy_balance, plot_energy, plot_run_energy
from .errors import (ErrorNorms, ExpressionError, compile_expression, error_norms,
                     exact_values, field_component, particle_error)
from .io import list_outputs, load_grid, load_history, load_particles, output_at
from .pore import load_pore_pressure
from .profiles import (failure_surface, free_surface, height_at_wall, load_reference_profile,
                       max_height, rms_height_difference, slip_angle, toe_position)

__all__ = [
    "ErrorNorms",
    "ExpressionError",
    "compile_expression",
    "describe_drift",
    "energy_balance",
    "error_norms",
    "exact_values",
    "failure_surface",
    "field_component",
    "free_surface",
    "height_at_wall",
    "list_outputs",
    "load_grid",
    "load_history",
    "load_particles",
    "load_pore_pressure",
    "load_reference_profile",
    "max_height",
    "output_at",
    "particle_error",
    "plot_energy",
    "plot_run_energy",
    "rms_height_difference",
    "slip_angle",
    "toe_position",
]
__version__ = "0.1.0"
