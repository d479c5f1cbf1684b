"""Check that the XDMF index of a run on several images opens in ParaView as one time series.

Usage (headless): pvbatch tests/parallel/check_parts_paraview.py RUN/<case>.xdmf EXPECTED_N

Opens the index with Xdmf3ReaderS (the reader docs/output.md recommends) and checks that it has
as many time steps as the index lists, that at the last time the particle blocks of all parts
hold EXPECTED_N particles together, each id once, and that every block carries "id",
"velocity" and "stress_xx". Exit status 1 when a check fails, 2 on bad usage.
"""

import os
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np
from paraview import servermanager
from paraview import simple
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cli"))
from check_xdmf_paraview import leaves  # noqa: E402  (the same walk over the reader output)


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    path, expected_n = os.path.abspath(argv[1]), int(argv[2])
    failures = []

    def check(condition, what):
        print(("ok   " if condition else "FAIL ") + what)
        if not condition:
            failures.append(what)

    root = ElementTree.parse(path).getroot()
    n_declared = len(root.find("Domain").find("Grid").findall("Grid"))
    reader = simple.Xdmf3ReaderS(FileName=[path])
    times = reader.TimestepValues
    times = list(times) if hasattr(times, "__len__") else [times]
    check(len(times) == n_declared, f"time steps: {len(times)} (the index lists {n_declared})")
    reader.UpdatePipeline(times[-1])
    blocks = [b for b in leaves(servermanager.Fetch(reader)) if b.GetNumberOfPoints() > 0]
    check(len(blocks) >= 2, f"particle blocks at the last time: {len(blocks)} (one per part)")
    total = sum(b.GetNumberOfPoints() for b in blocks)
    check(total == expected_n, f"particles at the last time: {total} (expected {expected_n})")
    ids = []
    for b in blocks:
        data = b.GetPointData()
        names = {data.GetArrayName(i) for i in range(data.GetNumberOfArrays())}
        check({"id", "velocity", "stress_xx"} <= names,
              f"block of {b.GetNumberOfPoints()} particles has id, velocity, stress_xx")
        if "id" in names:
            ids.append(vtk_to_numpy(data.GetArray("id")))
    if ids:
        ids = np.sort(np.concatenate(ids))
        check(np.array_equal(ids, np.arange(1, expected_n + 1)), "ids 1..N, each once")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
