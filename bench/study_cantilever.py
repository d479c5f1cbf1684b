#!/usr/bin/env python3
"""The cantilever under sudden gravity of issue 19 (called by bench/run_study.sh, part
``cantilever``; docs/study/cantilever.md describes the case and holds the table).

    .venv/bin/python bench/study_cantilever.py --exe build/mpm_geo \
        --out docs/study/cantilever.csv --runs 0.25:bspline2:MUSL:flip:2 0.125:cpgimp:MUSL:apic:2

The beam of Sadeghirad et al. (2011), REFERENCES.md section 8: 4 m x 1 m, clamped at x = 0 (the
beam starts on the domain face xmin, boundary ``fixed``), neo-Hookean E = 1 MPa, nu = 0.3,
rho = 1050 kg/m3, gravity 10 m/s2 from t = 0, plane strain, no damping, CFL 0.5, to t = 3 s;
domain 4.5 m x 5.5 m with the beam at y = 4..5 (the other faces free and out of reach).

Each run is ``cells:shape:scheme:transfer:ppc`` (cell size [m], solver.shape_function,
solver.scheme, solver.transfer, particles per cell and axis). Measured:

- ``peak_m``: the largest downward displacement of the particle of the free end nearest the
  bottom corner (4, 4) (the published 3.31 m, CPDI; the particles keep their order on one image);
- ``residual_rel``: the ``residual`` of history.csv at the end of the run over the largest drop
  of the potential energy;
- ``end_s`` and ``exit``: the time reached and mpm_geo's exit code (3: stopped by the guard, a
  particle that left the grid or jumped more than a cell).

One CSV line per run, appended as soon as it ends (a failed run is a line, never a crash).
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "postproc"))

from mpm_post.cantilever import PUBLISHED_PEAK, cantilever_case, measure  # noqa: E402

FIELDS = ["cells_m", "shape", "scheme", "transfer", "ppc", "particles", "peak_m", "peak_rel",
          "residual_rel", "end_s", "exit", "note"]
RUN_TIMEOUT = 7200.0      # [s]
__all__ = ["cantilever_case", "main", "parse_run", "run_one"]


def run_one(exe, dx, shape, scheme, transfer, ppc, workdir):
    """Run one case and measure it; returns the CSV row."""
    case = cantilever_case(dx, shape, scheme, transfer, ppc)
    case_path = Path(workdir) / f"{case['name']}.json"
    case_path.write_text(json.dumps(case, indent=1), encoding="utf-8")
    output = Path(workdir) / case["name"]
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "1"))
    row = {"cells_m": dx, "shape": shape, "scheme": scheme, "transfer": transfer, "ppc": ppc}
    try:
        result = subprocess.run([str(exe), str(case_path), "--output", str(output),
                                 "--overwrite"], capture_output=True, text=True, check=False,
                                timeout=RUN_TIMEOUT, env=env)
        row["exit"] = result.returncode
        errors = [line for line in result.stderr.splitlines() if "error" in line]
        row["note"] = errors[0][:200] if errors else ""
    except subprocess.TimeoutExpired:
        row["exit"] = "timeout"
        row["note"] = f"longer than {RUN_TIMEOUT:g} s"
    try:
        measured = measure(output)
        row["particles"] = measured["particles"]
        row["peak_m"] = f"{measured['peak_m']:.4f}"
        row["peak_rel"] = f"{measured['peak_m'] / PUBLISHED_PEAK - 1.0:+.4f}"
        row["residual_rel"] = f"{measured['residual_rel']:+.4f}"
        row["end_s"] = f"{measured['end_s']:.2f}"
    except (OSError, KeyError, IndexError, ValueError) as exc:
        row["note"] = (row.get("note", "") + f" analysis failed: {exc}")[:200]
    return row


def parse_run(text):
    """``cells:shape:scheme:transfer:ppc`` to a tuple."""
    parts = text.split(":")
    if len(parts) != 5:
        raise argparse.ArgumentTypeError(f"'{text}': expected cells:shape:scheme:transfer:ppc")
    return float(parts[0]), parts[1], parts[2], parts[3], int(parts[4])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--exe", required=True, help="mpm_geo")
    parser.add_argument("--out", required=True, help="CSV file the rows are appended to")
    parser.add_argument("--runs", nargs="+", type=parse_run, required=True,
                        help="cells:shape:scheme:transfer:ppc, one per run")
    args = parser.parse_args(argv)
    out = Path(args.out)
    new = not out.exists()
    with out.open("a", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=FIELDS)
        if new:
            writer.writeheader()
        with tempfile.TemporaryDirectory(prefix="mpm_cantilever_") as workdir:
            for run in args.runs:
                row = run_one(Path(args.exe).resolve(), *run, workdir)
                writer.writerow(row)
                handle.flush()
                print(" ".join(f"{k}={row.get(k, '')}" for k in FIELDS), flush=True)


if __name__ == "__main__":
    main()
