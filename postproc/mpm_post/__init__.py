"""Read and summarise the outputs of mpm-geo runs.

A run directory (``outputs/<case>/``) holds ``particles_NNNNNN.h5`` files, one per output time,
a ``<case>.xdmf`` index for ParaView and ``history.csv`` with the energy balance.
Layout: docs/output.md.
"""

from .energy import energy_drift, plot_energy
from .io import list_outputs, load_grid, load_history, load_particles
from .profiles import (failure_surface, free_surface, height_at_wall, load_reference_profile,
                       rms_height_difference, slip_angle, toe_position)

__all__ = [
    "energy_drift",
    "failure_surface",
    "free_surface",
    "height_at_wall",
    "list_outputs",
    "load_grid",
    "load_history",
    "load_particles",
    "load_reference_profile",
    "plot_energy",
    "rms_height_difference",
    "slip_angle",
    "toe_position",
]
__version__ = "0.1.0"
