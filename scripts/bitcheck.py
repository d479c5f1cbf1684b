#!/usr/bin/env python3
"""Compare the outputs of two builds of mpm_geo, bit for bit (a refactor must not change them).

Runs every case of inputs/, validation/ and bench/cases/ (or the ones given) with both
executables, each into its own temporary folder, and compares every output file: HDF5 files
dataset by dataset and attribute by attribute (exact values, NaNs equal, same dtype and shape;
HDF5's object time stamps differ between any two runs), text files (history.csv, XDMF) byte
for byte, and the exit codes. State files a case writes or reads (save_state, load_state,
checkpoint.file) are moved into the temporary folder, so outputs/ is never touched, and a
case that writes a state file runs before the cases that read it.

Usage (from the repository root, with the project's .venv):
    .venv/bin/python scripts/bitcheck.py --ref /tmp/ref/mpm_geo --new build/mpm_geo
    .venv/bin/python scripts/bitcheck.py --ref A --new B --full          # to each case's tend
    .venv/bin/python scripts/bitcheck.py --ref A --new B inputs/base_case.json
By default each case runs to --fraction (0.1) of its end time (at least --min-steps steps are
reached in practice by every shipped case); --full runs every case to its own end.
Exit code 0 when every case gives the same files, 1 otherwise.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def default_cases():
    cases = sorted(ROOT.glob("inputs/*.json"))
    cases += sorted(p for p in ROOT.glob("validation/*/*.json"))
    cases += sorted(ROOT.glob("bench/cases/*.json"))
    return cases


def state_path(tmp, path):
    """Where a state file named in a case goes in the temporary folder of one side."""
    return str(Path(tmp) / "states" / path.replace("/", "__"))


def prepare(case_file, tmp, fraction):
    """The case with its state files moved to tmp and its end time cut; its name."""
    data = json.loads(Path(case_file).read_text())
    for key in ("save_state", "load_state"):
        if isinstance(data.get(key), str) and data[key]:
            data[key] = state_path(tmp, data[key])
    ck = data.get("checkpoint")
    if isinstance(ck, dict) and isinstance(ck.get("file"), str):
        ck["file"] = state_path(tmp, ck["file"])
    if fraction < 1.0 and isinstance(data.get("time"), dict) and "tend" in data["time"]:
        data["time"]["tend"] = data["time"]["tend"] * fraction
    return data


def run(exe, case_file, tmp, fraction, label):
    data = prepare(case_file, tmp, fraction)
    name = data.get("name", Path(case_file).stem)
    case_dir = Path(tmp) / "cases"
    case_dir.mkdir(parents=True, exist_ok=True)
    (Path(tmp) / "states").mkdir(exist_ok=True)
    # the file name is the default case name: keep it
    path = case_dir / Path(case_file).name
    path.write_text(json.dumps(data))
    out = Path(tmp) / "out" / label
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_DYNAMIC="false")
    proc = subprocess.run([str(exe), str(path), "-o", str(out), "--overwrite", "-q"],
                          cwd=ROOT, env=env, capture_output=True, text=True)
    return proc.returncode, out, proc.stderr.strip(), name


def h5_items(path):
    items = {}

    def visit(name, obj):
        items[name] = obj

    with h5py.File(path, "r") as f:
        out = {}
        f.visititems(visit)
        for key in [""] + list(items):
            obj = f[key] if key else f
            for aname, aval in obj.attrs.items():
                out[f"{key}@{aname}"] = np.asarray(aval)
            if isinstance(obj, h5py.Dataset):
                out[key] = obj[()]
    return out


# Provenance a state file records about its run, different between any two runs: where the
# case and the output were (each side has its own temporary folder) and the wall-clock time.
PROVENANCE = {"run@case_file", "run@output_dir", "run@wall"}


def same_array(a, b):
    a = np.asarray(a)
    b = np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.kind == "f":
        return a.tobytes() == b.tobytes()
    return bool(np.array_equal(a, b))


def compare_dirs(a, b):
    """Differences between two output folders, as text lines."""
    problems = []
    fa = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    fb = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    fa = [p for p in fa if p.name != ".mpm_geo.lock"]
    fb = [p for p in fb if p.name != ".mpm_geo.lock"]
    if fa != fb:
        problems.append(f"file lists differ: only ref {sorted(set(fa) - set(fb))}, "
                        f"only new {sorted(set(fb) - set(fa))}")
    for rel in sorted(set(fa) & set(fb)):
        pa, pb = a / rel, b / rel
        if rel.suffix == ".h5":
            ia, ib = h5_items(pa), h5_items(pb)
            if set(ia) != set(ib):
                problems.append(f"{rel}: objects differ: only ref {sorted(set(ia) - set(ib))}, "
                                f"only new {sorted(set(ib) - set(ia))}")
            for key in sorted((set(ia) & set(ib)) - PROVENANCE):
                if not same_array(ia[key], ib[key]):
                    problems.append(f"{rel}: {key} differs")
        elif pa.read_bytes().replace(bytes(a), b"<out>") != \
                pb.read_bytes().replace(bytes(b), b"<out>"):
            # (a strength reduction's table names its trial folders, inside each run's own)
            problems.append(f"{rel} differs")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--ref", required=True, help="mpm_geo before the change")
    parser.add_argument("--new", required=True, help="mpm_geo after the change")
    parser.add_argument("--fraction", type=float, default=0.1,
                        help="fraction of each case's end time to run (default 0.1)")
    parser.add_argument("--full", action="store_true", help="run every case to its end time")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder")
    parser.add_argument("cases", nargs="*", help="case files (default: every shipped case)")
    args = parser.parse_args()
    fraction = 1.0 if args.full else args.fraction
    cases = [Path(c).resolve() for c in args.cases] or default_cases()
    # writers of state files first
    cases.sort(key=lambda c: 0 if "save_state" in json.loads(c.read_text()) else 1)
    tmp = Path(tempfile.mkdtemp(prefix="bitcheck."))
    failures = 0
    for case in cases:
        rel = case.relative_to(ROOT) if case.is_relative_to(ROOT) else case
        results = []
        for side, exe in (("ref", args.ref), ("new", args.new)):
            results.append(run(Path(exe).resolve(), case, tmp / side, fraction, case.stem))
        (rc_a, out_a, err_a, _), (rc_b, out_b, err_b, _) = results
        problems = []
        if rc_a != rc_b:
            problems.append(f"exit codes {rc_a} (ref) and {rc_b} (new): {err_b or err_a}")
        problems += compare_dirs(out_a, out_b)
        status = "same" if not problems else "DIFFERENT"
        print(f"{status:9s} {rel} (exit {rc_a})", flush=True)
        for line in problems[:20]:
            print("          " + line)
        failures += bool(problems)
    if not args.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    else:
        print(f"outputs kept in {tmp}")
    print(f"{len(cases) - failures} of {len(cases)} cases give the same outputs")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
