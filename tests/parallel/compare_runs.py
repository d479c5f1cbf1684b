"""Compare the last output of a serial run with that of a run on several images.

usage: compare_runs.py SERIAL_DIR PARALLEL_DIR [--rtol R] [--images N] [--min-part M]

The parallel run writes one part per image (particles_NNNNNN_pKKKKK.h5) with the id of each
particle (its index in the serial run); it must have N parts (default 2; with N = 1 the
second folder holds a serial run too), each with at least M particles at the last output
(the cuts followed the particles). The check: the same particle count and total mass
exactly, every id once, positions and stresses equal to round-off (relative to the size of
the field), and the energy history (history.csv) equal to round-off column by column. Exit code 0 when they agree, 1 otherwise, with what differs.
"""

import argparse
import glob
import os
import sys

import h5py
import numpy as np


def last_index(folder, pattern):
    """Highest output index NNNNNN of the files matching pattern (a glob with the index)."""
    files = glob.glob(os.path.join(folder, pattern))
    if not files:
        raise SystemExit(f"compare_runs: no output files {pattern} in {folder}")
    return max(int(os.path.basename(f).split("_")[1].split(".")[0]) for f in files)


def read_serial(folder):
    index = last_index(folder, "particles_[0-9][0-9][0-9][0-9][0-9][0-9].h5")
    with h5py.File(os.path.join(folder, f"particles_{index:06d}.h5"), "r") as f:
        data = {k: f["particles"][k][()] for k in f["particles"]}
        time = f.attrs["time"]
    data["id"] = np.arange(1, len(data["position"]) + 1)
    return index, time, data


def read_parallel(folder, index, images):
    if images == 1:
        _, time, data = read_serial(folder)
        return {float(time)}, [len(data["position"])], data
    parts = sorted(glob.glob(os.path.join(folder, f"particles_{index:06d}_p*.h5")))
    if len(parts) != images:
        raise SystemExit(f"compare_runs: {len(parts)} parts of output {index} in {folder}, "
                         f"expected {images}")
    fields = {}
    times = set()
    counts = []
    for part in parts:
        with h5py.File(part, "r") as f:
            times.add(float(f.attrs["time"]))
            group = f["particles"]
            counts.append(len(group["position"]))
            for k in group:
                fields.setdefault(k, []).append(group[k][()])
    data = {k: np.concatenate(v) for k, v in fields.items()}
    return times, counts, data


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("serial")
    parser.add_argument("parallel")
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--images", type=int, default=2)
    parser.add_argument("--min-part", type=int, default=0)
    args = parser.parse_args()

    index, time, ser = read_serial(args.serial)
    times, counts, par = read_parallel(args.parallel, index, args.images)
    failures = []
    if times != {float(time)}:
        failures.append(f"output {index}: times {sorted(times)} against {time}")
    n = len(ser["position"])
    if len(par["position"]) != n:
        failures.append(f"particle count {len(par['position'])} against {n}")
    ids = np.sort(par["id"])
    if not np.array_equal(ids, np.arange(1, n + 1)):
        failures.append("the ids of the parts are not 1..n, each once")
    if min(counts) < args.min_part:
        failures.append(f"parts of {counts} particles: one has fewer than {args.min_part}")
    if failures:
        print("\n".join(failures))
        return 1
    order = np.argsort(par["id"])
    for k in par:
        par[k] = par[k][order]
    # total mass exactly: the same particles, whatever their image
    if "mass" in ser and not np.array_equal(np.sort(ser["mass"]), np.sort(par["mass"])):
        failures.append("particle masses differ")
    if "mass" in ser and ser["mass"].sum() != par["mass"].sum():
        failures.append(f"total mass {par['mass'].sum()!r} against {ser['mass'].sum()!r}")
    report = []
    for field in ("position", "velocity", "stress", "plastic_strain"):
        if field not in ser:
            continue
        a, b = ser[field], par[field]
        scale = max(np.abs(a).max(), 1e-300)
        if field == "position":
            # positions: relative to the extent of the material
            scale = max(np.ptp(a, axis=0).max(), 1e-300)
        err = np.abs(a - b).max() / scale
        report.append(f"{field}: max |serial - parallel| / scale = {err:.3e}")
        if err > args.rtol:
            failures.append(f"{field} differs: {err:.3e} > {args.rtol:.1e} (relative)")
    # the energy history: the same rows, each energy column to round-off of its largest value
    # (the damping work counts each shared node once: on the image that owns it)
    hist_a = np.genfromtxt(os.path.join(args.serial, "history.csv"), delimiter=",", names=True)
    hist_b = np.genfromtxt(os.path.join(args.parallel, "history.csv"), delimiter=",", names=True)
    if hist_a.shape != hist_b.shape or not np.array_equal(hist_a["step"], hist_b["step"]):
        failures.append(f"history.csv: {hist_b.size} rows against {hist_a.size}, or other steps")
    else:
        worst, column = 0.0, ""
        for name in hist_a.dtype.names:
            if name == "step":
                continue
            scale = max(np.abs(hist_a[name]).max(), 1e-300)
            err = float(np.abs(hist_a[name] - hist_b[name]).max() / scale)
            if err > worst:
                worst, column = err, name
        report.append(f"history.csv: max relative difference {worst:.3e} ({column or '-'})")
        if worst > args.rtol:
            failures.append(f"history.csv differs: {column} {worst:.3e} > {args.rtol:.1e}")
    print(f"output {index} (t = {time:.6g} s), {n} particles on {len(counts)} images "
          f"({', '.join(str(c) for c in counts)})")
    print("\n".join(report))
    if failures:
        print("\n".join(failures))
        return 1
    print("the runs agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())
