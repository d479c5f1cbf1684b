"""Read and summarise the outputs of mpm-geo runs.

A run directory (``outputs/<case>/``) holds ``particles_NNNNNN.h5`` files, one per output time,
a ``<case>.xdmf`` index for ParaView and ``history.csv`` with the energy balance.
Layout: docs/output.md.
"""

from .energy import energy_drift, plot_energy
from .io import list_outputs, load_grid, load_history, load_particles

__all__ = [
    "energy_drift",
    "list_outputs",
    "load_grid",
    "load_history",
    "load_particles",
    "plot_energy",
]
__version__ = "0.1.0"
