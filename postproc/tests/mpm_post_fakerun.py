"""Small mpm-geo run directories written with h5py in the layout of docs/output.md.

A uniquely named module (not conftest) so that other test folders can have their own helpers.
"""

from pathlib import Path

import h5py
import numpy as np

POSTPROC = Path(__file__).resolve().parents[1]

HISTORY_HEADER = "time,step,kinetic_energy,strain_energy,potential_energy,damping_work,total"


def particle_fields(dim, n, time):
    """Deterministic particle data whose values depend on the output time."""
    rng = np.random.default_rng(1000 * dim + n)
    position = np.zeros((n, 3))
    position[:, :dim] = rng.uniform(0.0, 1.0, (n, dim))
    nstress = 4 if dim == 2 else 6
    return {
        "position": position,
        "displacement": np.full((n, 3), time) * (np.arange(3) < dim),
        "velocity": rng.normal(size=(n, 3)) * (np.arange(3) < dim),
        "stress": -1.0e3 * (1.0 + time) * np.arange(1, n * nstress + 1).reshape(n, nstress),
        "strain": 1.0e-4 * time * np.ones((n, nstress)),
        "material": np.arange(n, dtype=np.int32) % 2 + 1,
        "mass": np.full(n, 2.5),
        "volume": np.full(n, 1.25e-3),
    }


def write_output(path, time, step, dim, fields, case_name="test_case", fortran_style=False,
                 grid=None):
    """One particles_NNNNNN.h5 file.

    fortran_style stores the attributes the way the HDF5 Fortran API often does: 1-element
    arrays and a fixed-length, blank-padded byte string.
    """
    with h5py.File(path, "w") as h5file:
        if fortran_style:
            h5file.attrs["time"] = np.array([time])
            h5file.attrs["step"] = np.array([step], dtype=np.int32)
            h5file.attrs["dimension"] = np.array([dim], dtype=np.int32)
            h5file.attrs["case_name"] = np.bytes_(case_name.ljust(32))
        else:
            h5file.attrs["time"] = float(time)
            h5file.attrs["step"] = int(step)
            h5file.attrs["dimension"] = int(dim)
            h5file.attrs["case_name"] = case_name
        group = h5file.create_group("particles")
        for name, array in fields.items():
            group.create_dataset(name, data=array)
        if grid is not None:
            grid_group = h5file.create_group("grid")
            for name, array in grid.items():
                grid_group.create_dataset(name, data=array)
    return path


def write_history(path, rows):
    lines = [HISTORY_HEADER] + [",".join(f"{v:.17g}" for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def history_rows(n=5):
    """Energy terms with a known drift: total moves by 0.1 J per row after the first."""
    rows = []
    for i in range(n):
        time = 0.1 * i
        kinetic = 10.0 - 2.0 * i
        strain = 2.0 * i
        potential = -1.0 * i
        damping = 1.0 * i
        total = kinetic + strain + potential + damping + 0.1 * i
        rows.append((time, 10 * i, kinetic, strain, potential, damping, total))
    return rows


# A 2D column under gravity with a known error: the exact geostatic stress
# sigma_yy = -RHO G (HEIGHT - y) (tension positive) plus OFFSETS [Pa] at the last output.
RHO = 2650.0          # density [kg/m3]
G = 9.81              # gravity [m/s2]
HEIGHT = 0.1          # column height [m]
GEOSTATIC = "-2650*9.81*(0.1 - y)"
COLUMN_Y = np.array([0.0125, 0.0375, 0.0625, 0.0875])    # particle heights [m]
COLUMN_X = np.array([0.01, 0.03, 0.05, 0.07])            # particle x [m]
MASSES = np.array([1.0, 1.0, 2.0, 4.0])                  # [kg/m]
OFFSETS = np.array([1.0, -2.0, 0.5, 0.0])                # stress error [Pa]
SHIFT = 0.02                                             # x displacement at the last output [m]


def write_geostatic_run(run_dir, times=(0.0, 0.5)):
    """A run whose first output holds the exact stress and whose last one holds it + OFFSETS.

    Between them the particles move by SHIFT along x (displacement and position agree) and the
    x velocity is exactly t * x_initial, so that ``velocity x`` against ``t*x`` at the initial
    positions has no error. Volumes are all equal (1e-4 m2), masses are MASSES.
    """
    run_dir = Path(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    for index, time in enumerate(times):
        last = index == len(times) - 1 and index > 0
        displacement = np.zeros((4, 3))
        displacement[:, 0] = SHIFT if last else 0.0
        position = np.stack([COLUMN_X, COLUMN_Y, np.zeros(4)], axis=1) + displacement
        stress = np.zeros((4, 4))
        stress[:, 1] = -RHO * G * (HEIGHT - COLUMN_Y) + (OFFSETS if last else 0.0)
        velocity = np.zeros((4, 3))
        velocity[:, 0] = time * COLUMN_X
        write_output(run_dir / f"particles_{index:06d}.h5", time, 100 * index, 2,
                     {"position": position, "displacement": displacement, "velocity": velocity,
                      "stress": stress, "mass": MASSES.copy(), "volume": np.full(4, 1.0e-4)},
                     case_name="geostatic")
    write_history(run_dir / "history.csv", history_rows())
    return run_dir
