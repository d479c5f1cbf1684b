"""Check that an mpm-geo XDMF time series opens in ParaView.

Usage (headless, no display needed):

    pvbatch tests/cli/check_xdmf_paraview.py outputs/<case>/<case>.xdmf EXPECTED_N

Opens the file with ParaView's XDMF3 reader (Xdmf3ReaderS, the one the docs recommend) and
checks that
- there is at least one time step, and as many as the XDMF file lists;
- the particles at the last time number EXPECTED_N;
- every particle attribute the XDMF file declares is loaded, in particular "velocity" and
  "stress_xx" when written;
- "stress_xx" (a column of the stress dataset) equals component 0 of "stress";
- the grid, when written, loads as a regular mesh with its "mass" and "velocity".
Prints one line per check and exits with status 1 when any check fails, 2 on bad usage.
"""

import os
import sys
import xml.etree.ElementTree as ElementTree

from paraview import servermanager
from paraview import simple


def declared(path):
    """Number of times, and the last particles and grid <Grid> elements of the XDMF file."""
    root = ElementTree.parse(path).getroot()
    series = root.find("Domain").find("Grid")
    times = series.findall("Grid")
    if not times:
        return 0, None, None
    last = times[-1]
    if last.get("CollectionType") == "Spatial":
        return (len(times), last.find("Grid[@Name='particles']"),
                last.find("Grid[@Name='grid']"))
    return len(times), last, None


def leaves(data):
    """The datasets of a reader output, whatever the nesting (multiblock, multipiece)."""
    if data is None:
        return []
    if data.IsA("vtkMultiBlockDataSet"):
        return [leaf for i in range(data.GetNumberOfBlocks())
                for leaf in leaves(data.GetBlock(i))]
    if data.IsA("vtkMultiPieceDataSet"):
        return [leaf for i in range(data.GetNumberOfPieces())
                for leaf in leaves(data.GetPiece(i))]
    return [data]


def point_arrays(dataset):
    point_data = dataset.GetPointData()
    return {point_data.GetArrayName(i): point_data.GetArray(i)
            for i in range(point_data.GetNumberOfArrays())}


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    # the XDMF library resolves the .h5 names against the folder of an absolute path only
    path, expected_n = os.path.abspath(argv[1]), int(argv[2])
    failures = []

    def check(condition, what):
        print(("ok   " if condition else "FAIL ") + what)
        if not condition:
            failures.append(what)

    n_declared, particles_xml, grid_xml = declared(path)
    check(particles_xml is not None, "the XDMF file lists particles")
    if particles_xml is None:
        return 1

    reader = simple.Xdmf3ReaderS(FileName=[path])
    times = reader.TimestepValues
    times = list(times) if hasattr(times, "__len__") else [times]
    check(len(times) >= 1, "time steps: %d (at least 1)" % len(times))
    check(len(times) == n_declared, "time steps: %d, the XDMF file lists %d"
          % (len(times), n_declared))
    if not times:
        return 1
    reader.UpdatePipeline(times[-1])
    datasets = leaves(servermanager.Fetch(reader))
    particle_sets = [d for d in datasets if d.IsA("vtkUnstructuredGrid")]
    grid_sets = [d for d in datasets if d.IsA("vtkImageData")]
    check(len(particle_sets) == 1, "one particle dataset in the reader output (%d)"
          % len(particle_sets))
    if len(particle_sets) != 1:
        return 1
    particles = particle_sets[0]
    n = particles.GetNumberOfPoints()
    check(n == expected_n, "points at the last time t = %g: %d, expected %d"
          % (times[-1], n, expected_n))

    arrays = point_arrays(particles)
    names = [a.get("Name") for a in particles_xml.findall("Attribute")]
    for name in ("velocity", "stress_xx"):
        if name in names:
            check(name in arrays, "array '%s' loaded" % name)
    missing = [name for name in names if name not in arrays]
    check(not missing, "all %d declared particle arrays loaded (missing: %s)"
          % (len(names), missing))
    if "stress" in arrays and "stress_xx" in arrays:
        stress, stress_xx = arrays["stress"], arrays["stress_xx"]
        check(stress.GetNumberOfComponents() in (4, 6),
              "stress has %d components" % stress.GetNumberOfComponents())
        check(stress_xx.GetNumberOfComponents() == 1, "stress_xx is a scalar")
        check(all(stress.GetComponent(i, 0) == stress_xx.GetValue(i) for i in range(n)),
              "stress_xx equals component 0 of stress")

    if grid_xml is not None:
        check(len(grid_sets) == 1, "one grid dataset in the reader output (%d)" % len(grid_sets))
        if len(grid_sets) == 1:
            grid = grid_sets[0]
            grid_arrays = point_arrays(grid)
            check("mass" in grid_arrays and "velocity" in grid_arrays,
                  "grid arrays mass and velocity loaded")
            if "mass" in grid_arrays:
                check(grid.GetNumberOfPoints() == grid_arrays["mass"].GetNumberOfTuples(),
                      "grid: %d points, bounds %s" % (grid.GetNumberOfPoints(),
                                                      grid.GetBounds()))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
