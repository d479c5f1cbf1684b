"""Check that two output folders of mpm_geo hold the same results, bit for bit.

usage: compare_identical.py DIR_A DIR_B

Both folders must hold the same particle files (particles_NNNNNN.h5), each with the same
datasets holding the same bytes and the same time and step attributes; the energy
histories (history.csv) must be the same text. Used to check that a run stopped and
restarted from a checkpoint gives what a run that was never stopped gives. Exit code 0
when identical, 1 otherwise (with what differs).
"""

import glob
import os
import sys

import h5py
import numpy as np


def datasets(path):
    """Every dataset of an HDF5 file by name, and the file's time and step."""
    found = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: found.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
        attrs = (float(f.attrs["time"]), int(f.attrs["step"]))
    return found, attrs


def main(a, b):
    problems = []
    files_a = sorted(os.path.basename(p) for p in glob.glob(os.path.join(a, "particles_*.h5")))
    files_b = sorted(os.path.basename(p) for p in glob.glob(os.path.join(b, "particles_*.h5")))
    if not files_a:
        problems.append(f"no particle files in {a}")
    if files_a != files_b:
        problems.append(f"different particle files: {len(files_a)} in {a}, {len(files_b)} in {b}")
    for name in sorted(set(files_a) & set(files_b)):
        data_a, attrs_a = datasets(os.path.join(a, name))
        data_b, attrs_b = datasets(os.path.join(b, name))
        if attrs_a != attrs_b:
            problems.append(f"{name}: time/step {attrs_a} != {attrs_b}")
        if set(data_a) != set(data_b):
            problems.append(f"{name}: datasets {sorted(data_a)} != {sorted(data_b)}")
        for key in sorted(set(data_a) & set(data_b)):
            x, y = np.asarray(data_a[key]), np.asarray(data_b[key])
            if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                diff = ""
                if x.shape == y.shape and x.dtype.kind == "f":
                    diff = f", largest difference {np.nanmax(np.abs(x - y)):.3e}"
                problems.append(f"{name}: /{key} differs{diff}")
    hist_a = open(os.path.join(a, "history.csv")).read()
    hist_b = open(os.path.join(b, "history.csv")).read()
    if hist_a != hist_b:
        lines_a, lines_b = hist_a.splitlines(), hist_b.splitlines()
        first = next((i for i, (p, q) in enumerate(zip(lines_a, lines_b)) if p != q),
                     min(len(lines_a), len(lines_b)))
        problems.append(f"history.csv differs from line {first + 1} ({len(lines_a)} and "
                        f"{len(lines_b)} lines)")
    for p in problems:
        print("compare_identical:", p)
    if not problems:
        print(f"compare_identical: {len(files_a)} particle files and the history are identical")
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
