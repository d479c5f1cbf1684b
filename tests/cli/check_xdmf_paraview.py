"""Check that mpm-geo XDMF files open in ParaView, with both of its XDMF readers.

Usage (headless, no display needed), from the Python that has h5py (the project's .venv):

    .venv/bin/python tests/cli/check_xdmf_paraview.py [--pvbatch PVBATCH] FILE.xdmf [FILE.xdmf ...]

FILE is a run's time series index (<case>.xdmf, one image or the parts of several) or a
terrain.xdmf. The script first reads what ParaView must show from the HDF5 files themselves
(h5py): the times, the number of particles and of each material at the first and the last
time, the ids, the grid nodes and the terrain triangles. It then runs itself under pvbatch once
for all the files (`--expect EXPECT.json`, ParaView's Python has no h5py) and, for each file,
with Xdmf3ReaderS (what File > Open picks for .xdmf) and XDMFReader (the older Xdmf2 reader):

- as many time steps as the index lists, the first and last times as in the HDF5 files;
- at the first and the last time: as many points as particles, one vertex cell per particle;
  every attribute the index declares loaded with one value per particle; each stress_xx,
  strain_yy, ... equal to its column of stress, strain; the ids of all parts 1..N, each once;
- Threshold on `material`: for each material, exactly the particles of that material;
- the grid (when written): the node count, `mass` and `velocity` with their sums as in HDF5;
- nothing printed on stderr by the reader (HDF5 error blocks, skipped arrays);
- with Xdmf3ReaderT (collections), blocks named "particles" (and "grid");
- a terrain.xdmf: 3 points and one triangle per facet.

Prints one line per check ("ok   ..." / "FAIL ...") and exits with status 1 when a check fails,
2 on bad usage, and 77 (SKIP) when pvbatch is not installed.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

READERS = ("Xdmf3ReaderS", "XDMFReader")
SKIP = 77
VERTICES, VTK_TRIANGLE = (1, 2), 5
    # VTK_VERTEX, VTK_POLY_VERTEX; VTK_TRIANGLE
COMPONENTS = "xx yy zz xy yz zx".split()


# ---------------------------------------------------------------------------------------------
# The index (plain XML, read in both stages)
# ---------------------------------------------------------------------------------------------

def index_times(path):
    """The kind of the file ("series" or "terrain") and, for a series, per time the list of
    the particles <Grid> elements and the list of the grid <Grid> elements."""
    domain = ElementTree.parse(path).getroot().find("Domain")
    top = domain.find("Grid")
    if top.get("Name") == "terrain":
        return "terrain", []
    times = []
    for time in top.findall("Grid"):
        if time.get("GridType") == "Collection":
            times.append((time.findall("Grid[@Name='particles']"),
                          time.findall("Grid[@Name='grid']")))
        else:
            times.append(([time], []))
    return "series", times


def heavy_path(item, folder):
    """File and dataset of an HDF DataItem."""
    file_name, dataset = item.text.strip().split(":", 1)
    return os.path.join(folder, file_name), dataset


# ---------------------------------------------------------------------------------------------
# Stage 1 (Python with h5py): what the HDF5 files hold
# ---------------------------------------------------------------------------------------------

def expectations(path):
    """What ParaView must show for one file, read from the HDF5 files the index names."""
    import h5py
    import numpy as np

    folder = os.path.dirname(path)
    kind, times = index_times(path)
    if kind == "terrain":
        item = ElementTree.parse(path).getroot().find(".//Topology/DataItem")
        file_name, dataset = heavy_path(item, folder)
        with h5py.File(file_name, "r") as h5:
            triangles = h5[dataset].size // 3
        return {"path": path, "kind": kind, "triangles": int(triangles)}

    def at(index):
        particles, grids = times[index]
        n, ids, time = 0, [], None
        materials = {}
        for grid in particles:
            file_name, _ = heavy_path(grid.find("Geometry/DataItem"), folder)
            with h5py.File(file_name, "r") as h5:
                time = float(h5.attrs["time"])
                part = h5["particles"]
                n += part["position"].shape[0]
                if "material" in part:
                    for m, count in zip(*np.unique(part["material"][()], return_counts=True)):
                        materials[int(m)] = materials.get(int(m), 0) + int(count)
                if "id" in part:
                    ids.append(part["id"][()])
        nodes, mass, velocity = 0, 0.0, [0.0, 0.0, 0.0]
        for grid in grids:
            file_name, _ = heavy_path(grid.find("Attribute/DataItem"), folder)
            with h5py.File(file_name, "r") as h5:
                nodes += h5["grid/mass"].shape[0]
                mass += float(h5["grid/mass"][()].sum())
                velocity = [v + float(s) for v, s in zip(velocity, h5["grid/velocity"][()].sum(0))]
        return {"time": time, "particles": n, "materials": materials, "ids": bool(ids),
                "nodes": nodes, "mass": mass, "velocity": velocity}

    last = len(times) - 1
    first_particles = times[0][0][0] if times else None
    return {"path": path, "kind": kind, "times": len(times),
            "attributes": [a.get("Name") for a in first_particles.findall("Attribute")]
            if first_particles is not None else [],
            "grid": bool(times and times[0][1]),
            "collection": _is_collection(path),
            "checked": {str(i): at(i) for i in sorted({0, last})} if times else {}}


def _is_collection(path):
    top = ElementTree.parse(path).getroot().find("Domain").find("Grid")
    return any(g.get("GridType") == "Collection" for g in top.findall("Grid"))


def stage_one(argv):
    pvbatch = shutil.which("pvbatch")
    files = []
    args = iter(argv[1:])
    for arg in args:
        if arg == "--pvbatch":
            pvbatch = next(args, None)
        elif arg.startswith("-"):
            print(__doc__)
            return 2
        else:
            files.append(os.path.abspath(arg))
    if not files:
        print(__doc__)
        return 2
    if not pvbatch or not shutil.which(pvbatch):
        print("SKIP: pvbatch (ParaView) not found: the XDMF files are not opened in ParaView")
        return SKIP
    with tempfile.TemporaryDirectory() as scratch:
        expect = os.path.join(scratch, "expect.json")
        with open(expect, "w") as out:
            json.dump([expectations(f) for f in files], out)
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        return subprocess.run([pvbatch, os.path.abspath(__file__), "--expect", expect] + files,
                              env=env, check=False).returncode


# ---------------------------------------------------------------------------------------------
# Stage 2 (pvbatch): what the readers show
# ---------------------------------------------------------------------------------------------

class StderrCapture:
    """Collects what C++ code (the readers, HDF5) writes to file descriptor 2."""

    def __enter__(self):
        sys.stderr.flush()
        self.file = tempfile.TemporaryFile(mode="w+b")
        self.saved = os.dup(2)
        os.dup2(self.file.fileno(), 2)
        return self

    def __exit__(self, *exc):
        sys.stderr.flush()
        os.dup2(self.saved, 2)
        os.close(self.saved)
        self.file.seek(0)
        self.text = self.file.read().decode(errors="replace")
        self.file.close()
        return False


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


def block_names(data):
    """Names of the leaf blocks of a multiblock output."""
    names = []
    if data is not None and data.IsA("vtkMultiBlockDataSet"):
        for i in range(data.GetNumberOfBlocks()):
            block = data.GetBlock(i)
            if block is not None and block.IsA("vtkMultiBlockDataSet"):
                names += block_names(block)
            else:
                names.append(data.GetMetaData(i).Get(data.NAME()))
    return names


def stage_two(argv):
    import numpy as np
    from paraview import servermanager, simple
    from vtk.util.numpy_support import vtk_to_numpy

    if len(argv) < 4 or argv[1] != "--expect":
        print(__doc__)
        return 2
    with open(argv[2]) as source:
        expected = json.load(source)
    failures = []

    def check(condition, what):
        print(("ok   " if condition else "FAIL ") + what, flush=True)
        if not condition:
            failures.append(what)

    def open_reader(name, path):
        if name == "XDMFReader":
            return simple.XDMFReader(FileNames=[path])
        return getattr(simple, name)(FileName=[path])

    def arrays(dataset):
        data = dataset.GetPointData()
        return {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
                for i in range(data.GetNumberOfArrays())}

    def check_terrain(reader, label, want):
        reader.UpdatePipeline()
        sets = leaves(servermanager.Fetch(reader))
        points = sum(d.GetNumberOfPoints() for d in sets)
        cells = sum(d.GetNumberOfCells() for d in sets)
        types = np.concatenate([vtk_to_numpy(d.GetCellTypesArray()) for d in sets
                                if d.IsA("vtkUnstructuredGrid") and d.GetNumberOfCells()]
                               or [np.zeros(0)])
        check(points == 3 * want["triangles"] and cells == want["triangles"]
              and np.all(types == VTK_TRIANGLE),
              f"{label}: {cells} triangles, {points} points (expected {want['triangles']}, "
              f"{3 * want['triangles']})")

    def check_time(reader, label, time, want, attributes):
        reader.UpdatePipeline(time)
        sets = leaves(servermanager.Fetch(reader))
        particles = [d for d in sets if d.IsA("vtkUnstructuredGrid")]
        grids = [d for d in sets if not d.IsA("vtkUnstructuredGrid")]
        n = want["particles"]
        points = sum(d.GetNumberOfPoints() for d in particles)
        cells = sum(d.GetNumberOfCells() for d in particles)
        check(points == n, f"{label}: {points} points, expected {n} particles")
        check(cells == n, f"{label}: {cells} cells, expected one per particle ({n})")
        # XDMF's Polyvertex becomes VTK_POLY_VERTEX cells: each must hold one particle
        lone = all(np.isin(vtk_to_numpy(d.GetCellTypesArray()), VERTICES).all()
                   and np.array_equal(vtk_to_numpy(d.GetCells().GetConnectivityArray()),
                                      np.arange(d.GetNumberOfPoints()))
                   for d in particles if d.GetNumberOfCells())
        check(lone, f"{label}: each cell is a vertex of its own particle")
        ids = []
        for d in (d for d in particles if d.GetNumberOfPoints()):
            loaded = arrays(d)
            missing = [a for a in attributes if a not in loaded]
            check(not missing, f"{label}: all {len(attributes)} declared arrays loaded in a "
                  f"piece of {d.GetNumberOfPoints()} (missing: {missing})")
            short = [a for a in attributes
                     if a in loaded and len(loaded[a]) != d.GetNumberOfPoints()]
            check(not short, f"{label}: one value per particle (not so: {short})")
            for name in (a for a in attributes if a in loaded and a.count("_") == 1):
                tensor, component = name.split("_")
                if tensor not in loaded or component not in COMPONENTS:
                    continue
                column = COMPONENTS.index(component)
                check(np.array_equal(loaded[name], loaded[tensor][:, column]),
                      f"{label}: {name} equals column {column + 1} of {tensor}")
            if "id" in loaded:
                ids.append(loaded["id"])
        if want["ids"]:
            ids = np.sort(np.concatenate(ids)) if ids else np.zeros(0)
            check(np.array_equal(ids, np.arange(1, n + 1)), f"{label}: ids 1..{n}, each once")
        if want["nodes"]:
            nodes = sum(d.GetNumberOfPoints() for d in grids)
            check(nodes == want["nodes"], f"{label}: {nodes} grid nodes, expected {want['nodes']}")
            loaded = [arrays(d) for d in grids]
            have = all("mass" in a and "velocity" in a for a in loaded)
            check(have, f"{label}: grid arrays mass and velocity loaded")
            if have:
                mass = sum(float(a["mass"].sum()) for a in loaded)
                velocity = sum(a["velocity"].sum(0) for a in loaded)
                scale = max(1.0, abs(want["mass"]), *map(abs, want["velocity"]))
                check(abs(mass - want["mass"]) <= 1e-12 * scale
                      and np.allclose(velocity, want["velocity"], rtol=0, atol=1e-12 * scale),
                      f"{label}: grid mass and velocity sum as in the HDF5 files")
        for material, count in sorted(want["materials"].items(), key=lambda i: int(i[0])):
            m = int(material)
            threshold = simple.Threshold(Input=reader, Scalars=["POINTS", "material"],
                                         LowerThreshold=m, UpperThreshold=m)
            threshold.UpdatePipeline(time)
            kept = sum(d.GetNumberOfCells() for d in leaves(servermanager.Fetch(threshold)))
            check(kept == count, f"{label}: Threshold material = {m} keeps {kept} particles, "
                  f"the HDF5 files hold {count}")
            simple.Delete(threshold)

    for want in expected:
        path = want["path"]
        for name in READERS:
            label = f"{name} {os.path.basename(path)}"
            with StderrCapture() as err:
                reader = open_reader(name, path)
                if want["kind"] == "terrain":
                    check_terrain(reader, label, want)
                else:
                    steps = reader.TimestepValues
                    steps = list(steps) if hasattr(steps, "__len__") else [steps]
                    check(len(steps) == want["times"], f"{label}: {len(steps)} time steps, the "
                          f"index lists {want['times']}")
                    for index, at in sorted(want["checked"].items(), key=lambda i: int(i[0])):
                        index = int(index)
                        if index >= len(steps):
                            continue
                        time = steps[index]
                        check(abs(time - at["time"]) <= 1e-12 * max(1.0, abs(at["time"])),
                              f"{label}: time {index} is t = {time:g} as in the HDF5 file")
                        check_time(reader, f"{label} t = {time:g}", time, at,
                                   want["attributes"])
                simple.Delete(reader)
            check(not err.text.strip(), f"{label}: nothing printed on stderr"
                  + ("" if not err.text.strip() else ":\n" + "\n".join(err.text.splitlines()[:8])))
        if want["kind"] == "series" and want["collection"]:
            with StderrCapture() as err:
                reader = simple.Xdmf3ReaderT(FileName=[path])
                steps = reader.TimestepValues
                steps = list(steps) if hasattr(steps, "__len__") else [steps]
                reader.UpdatePipeline(steps[-1] if steps else 0.0)
                # the reader numbers repeated names: "particles[2]" is a "particles" block
                names = {name.split("[")[0] for name in block_names(servermanager.Fetch(reader))}
                simple.Delete(reader)
            wanted = {"particles", "grid"} if want["grid"] else {"particles"}
            check(names == wanted and not err.text.strip(),
                  f"Xdmf3ReaderT {os.path.basename(path)}: blocks {sorted(names)}, expected "
                  f"{sorted(wanted)}, stderr {'empty' if not err.text.strip() else err.text[:200]}")
    return 1 if failures else 0


if __name__ == "__main__":
    try:
        import paraview  # noqa: F401  (pvbatch: stage 2)
    except ImportError:
        sys.exit(stage_one(sys.argv))
    sys.exit(stage_two(sys.argv))
