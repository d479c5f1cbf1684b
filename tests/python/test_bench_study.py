"""Tests of the accuracy-against-cost study of the column and the Bui collapse (bench/):
study_report (orders, Pareto fronts, recommendations, findings) on synthetic runs, and the
parts of study_cases that need no mpm_geo run (exact column solution, error norms, the Bui case
copies, failed runs recorded as failures)."""

import csv
import math
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "bench"))

import study_cases  # noqa: E402
import study_report  # noqa: E402

FIELDS = ["problem", "shape", "scheme", "cells", "dx_m", "particles", "steps", "wall_s",
          "cpu_s", "error", "status", "note"]


def run(shape, scheme, cells, error, cpu, status="ok", note=""):
    """One synthetic row as load_runs returns it."""
    ok = status == "ok"
    return {"problem": "column", "shape": shape, "scheme": scheme, "cells": cells,
            "dx_m": 0.1 / cells, "particles": 8 * cells if ok else 0,
            "steps": 10 * cells if ok else 0, "wall_s": 2 * cpu if ok else math.nan,
            "cpu_s": cpu if ok else math.nan, "error": error if ok else math.nan,
            "status": status, "note": note}


def ladder():
    """cpgimp MUSL second order, linear MUSL first order then growing, one failed run."""
    rows = []
    for cells in (4, 8, 16, 32):
        rows.append(run("linear", "MUSL", cells,
                        0.2 / cells if cells < 32 else 0.2 / 8, 1e-3 * cells**2))
        rows.append(run("cpgimp", "MUSL", cells, 1.0 / cells**2, 2e-3 * cells**2))
    rows.append(run("linear", "USF", 4, math.nan, math.nan, status="failed",
                    note="particle 3 left the grid"))
    return rows


METRIC = study_report.Metric(key="error", title="Test: error", label="relative error",
                             targets=[0.1, 1e-2, 1e-3, 1e-5], figure="test")


def test_load_runs_converts_numbers_and_keeps_failures(tmp_path):
    path = tmp_path / "runs.csv"
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerow({"problem": "column", "shape": "cpgimp", "scheme": "USL", "cells": "8",
                         "dx_m": "0.0125", "particles": "64", "steps": "641", "wall_s": "0.1",
                         "cpu_s": "0.05", "error": "0.031", "status": "ok", "note": ""})
        writer.writerow({"problem": "column", "shape": "linear", "scheme": "USF", "cells": "8",
                         "dx_m": "0.0125", "status": "failed", "note": "exit code 3"})
    rows = study_report.load_runs(path)
    assert rows[0]["cells"] == 8 and rows[0]["error"] == pytest.approx(0.031)
    assert rows[1]["status"] == "failed" and math.isnan(rows[1]["wall_s"])
    assert rows[1]["particles"] == 0
    assert not study_report.usable(rows[1], "error")
    assert study_report.usable(rows[0], "error", "cpu_s")


def test_load_runs_refuses_an_empty_file(tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text(",".join(FIELDS) + "\n")
    with pytest.raises(ValueError, match="no run"):
        study_report.load_runs(path)


def test_orders_of_exact_power_laws():
    table = {(e["shape"], e["scheme"]): e for e in study_report.orders(ladder(), "error")}
    gimp = table[("cpgimp", "MUSL")]
    assert gimp["order"] == pytest.approx(2.0)
    assert gimp["stderr"] == pytest.approx(0.0, abs=1e-9)
    assert gimp["finest3"] == pytest.approx(2.0)
    assert gimp["local"] == pytest.approx([2.0, 2.0, 2.0])
    linear = table[("linear", "MUSL")]
    assert linear["local"] == pytest.approx([1.0, 1.0, -1.0])  # error grows from 16 to 32
    failed = table[("linear", "USF")]
    assert failed["runs"] == 0 and math.isnan(failed["order"])


def test_front_and_recommendation_use_the_cost_column():
    rows = ladder()
    front = study_report.front(rows, "error", "cpu_s")
    points = [(r["cpu_s"], r["error"]) for r in front]
    assert points == sorted(points)                      # cheapest first ...
    assert all(a[1] > b[1] for a, b in zip(points, points[1:]))   # ... and ever more accurate
    usable = [r for r in rows if study_report.usable(r, "error", "cpu_s")]
    for f in front:  # no run beats a front run in both
        assert not any(o["cpu_s"] < f["cpu_s"] and o["error"] < f["error"] for o in usable)
    for r in usable:  # and every run off the front is beaten by one on it
        if r not in front:
            assert any(f["cpu_s"] <= r["cpu_s"] and f["error"] <= r["error"] for f in front)
    best = study_report.fastest_reaching(rows, "error", 0.02, "cpu_s")
    # candidates: linear 16 cells (0.0125, 0.256 s), cpgimp 8 (0.0156, 0.128 s), ...
    assert (best["shape"], best["cells"]) == ("cpgimp", 8)
    assert study_report.fastest_reaching(rows, "error", 1e-9, "cpu_s") is None
    # by wall time (twice the CPU time here) the same run wins
    assert study_report.fastest_reaching(rows, "error", 0.02)["cells"] == 8


def test_describe_order():
    assert study_report.describe_order(2.1) == "about second order"
    assert study_report.describe_order(0.95) == "about first order"
    assert study_report.describe_order(0.1) == "no convergence"
    assert study_report.describe_order(-0.8) == "the error grows with refinement"
    assert "fewer than two" in study_report.describe_order(math.nan)


def test_findings_come_from_the_numbers():
    rows = ladder()
    table = study_report.orders(rows, "error")
    text = " ".join(study_report.findings(rows, METRIC, table,
                                          study_report.front(rows, "error", "cpu_s")))
    assert "cpgimp: observed order 2.00" in text and "about second order" in text
    assert "linear MUSL stops converging" in text and "16 to 32 cells" in text
    assert "Failed runs (1 of 9), left out of the fits: linear USF at 4 cells" in text
    assert "particle 3 left the grid" in text
    # cpgimp / linear at MUSL: 4 cells 0.0625 / 0.05, ..., 32 cells 0.000977 / 0.025
    assert "Error of cpgimp / error of linear" in text
    assert "at the finest resolution both finished: MUSL 0.0391 at 32 cells" in text


def test_reason_of_a_failed_run():
    note = ("mpm_geo exit code 3: step 2139, t =  4.95924E-01 s: particle 480 left the grid: "
            "position (4.8712E-01, 1.2002E-01) m; enlarge the domain")
    assert study_report.reason(note) == "t = 0.496 s: particle 480 left the grid"
    assert study_report.reason("no result after 3600 s") == "no result after 3600 s"
    assert study_report.reason("x" * 300).endswith("...")


def test_shapes_that_agree_are_said_to_agree():
    rows = [run(shape, "USL", cells, 0.1 / cells * (1.01 if shape == "cpgimp" else 1.0), 1.0)
            for shape in ("linear", "cpgimp") for cells in (4, 8)]
    text = " ".join(study_report.compare_shapes(rows, METRIC, ["linear", "cpgimp"]))
    assert "about the same error (ratio 1.01 to 1.01 over 2 pairs)" in text


def test_metric_section_writes_figures_and_tables(tmp_path):
    rows = ladder()
    lines = study_report.metric_section(rows, METRIC, tmp_path / "study", tmp_path, "cpu_s",
                                        "CPU time [s]")
    page = "\n".join(lines)
    for stem in ("test_cost", "test_convergence"):
        png = tmp_path / "study" / f"{stem}.png"
        assert png.stat().st_size > 1000
        assert f"(study/{stem}.png)" in page
    assert "| cpgimp | MUSL | 4 | 2.00 |" in page
    assert "| 1e-05 | none of the runs reaches it | - | - |" in page
    assert "Pareto front" in page


def test_runs_table_lists_failures_with_their_reason():
    lines = study_report.runs_table(ladder(), [("error", "error", 1.0)])
    assert len(lines) == 2 + 9
    assert any("failed: particle 3 left the grid" in line for line in lines)


# --------------------------------------------------------------------------- study_cases

def test_column_exact_solution():
    rho_g, e, h = (study_cases.COLUMN_RHO * study_cases.GRAVITY, study_cases.COLUMN_E,
                   study_cases.COLUMN_HEIGHT)
    y = np.linspace(0.0, h, 11)
    u = study_cases.column_exact_displacement(y)
    assert u[0] == 0.0
    # small-strain formula of REFERENCES.md (nu = 0), within the largest strain rho g H / E
    small = -rho_g / e * (h * y - y**2 / 2)
    assert np.allclose(u, small, rtol=rho_g * h / e, atol=0.0)
    # u' = exp(sigma / E) - 1: the stretch of sigma = E ln(stretch)
    slope = np.gradient(study_cases.column_exact_displacement(np.linspace(0, h, 20001)),
                        h / 20000)
    stress = study_cases.column_exact_stress(np.linspace(0, h, 20001))
    assert np.allclose(slope[1:-1], np.expm1(stress / e)[1:-1], atol=1e-9)


def column_output(cells, stress):
    """Particles of a column at rest with 2 x 2 particles per cell, the exact displacement
    and the vertical stress ``stress(y_ref, dx)``."""
    dx = study_cases.COLUMN_HEIGHT / cells
    y_ref = np.repeat((np.arange(2 * cells) + 0.5) * dx / 2, 4)
    u = study_cases.column_exact_displacement(y_ref)
    n = y_ref.size
    position = np.zeros((n, 3))
    position[:, 1] = y_ref + u
    displacement = np.zeros((n, 3))
    displacement[:, 1] = u
    sigma = np.zeros((n, 4))
    sigma[:, 1] = stress(y_ref, dx)
    return {"position": position, "displacement": displacement, "stress": sigma,
            "volume": np.full(n, dx * dx / 4), "mass": np.full(n, 1.0)}, dx


def test_column_errors_of_the_exact_field_vanish():
    data, dx = column_output(8, lambda y, dx: study_cases.column_exact_stress(y))
    errors = study_cases.column_errors(data, dx)
    for key in ("stress_l2_rel", "base_stress_rel", "settlement_rel", "displacement_l2_rel"):
        assert errors[key] == pytest.approx(0.0, abs=1e-12)


def test_column_stress_constant_per_cell_is_dx_over_4h():
    def per_cell(y, dx):
        return study_cases.column_exact_stress((np.floor(y / dx) + 0.5) * dx)

    for cells in (4, 16):
        data, dx = column_output(cells, per_cell)
        errors = study_cases.column_errors(data, dx)
        assert errors["stress_l2_rel"] == pytest.approx(dx / (4 * study_cases.COLUMN_HEIGHT))


def test_column_case_ladder():
    case = study_cases.column_case(16, "cpgimp", "USF")
    assert case["domain"]["dx"] == pytest.approx(study_cases.COLUMN_HEIGHT / 16)
    assert case["solver"] == {"scheme": "USF", "shape_function": "cpgimp"}
    assert case["bodies"][0]["max"][1] == study_cases.COLUMN_HEIGHT
    assert case["damping"] == {"type": "kinetic"}


def test_bui_case_changes_only_numerics_and_cell_size():
    import check  # validation/bui2008/check.py, on the path through study_cases
    original = check.load_case(check.CASE)
    case = study_cases.bui_case(check, 0.005, "linear", "USL")
    assert case["domain"]["dx"] == 0.005
    assert case["domain"]["nx"] * 0.005 == pytest.approx(
        original["domain"]["nx"] * original["domain"]["dx"])
    assert case["solver"]["shape_function"] == "linear" and case["solver"]["scheme"] == "USL"
    for key, value in original["solver"].items():
        if key not in ("shape_function", "scheme"):
            assert case["solver"][key] == value
    assert case["materials"] == original["materials"]
    assert case["domain"]["boundaries"] == original["domain"]["boundaries"]
    assert case["time"] == original["time"]


@pytest.fixture
def failing_exe(tmp_path):
    exe = tmp_path / "mpm_geo_fails"
    exe.write_text("#!/bin/sh\necho 'mpm_geo: case started'\n"
                   "echo 'mpm_geo: error: step 12: particle 7 left the grid' >&2\nexit 3\n")
    exe.chmod(0o755)
    return exe


def test_a_failed_run_is_recorded_not_raised(tmp_path, failing_exe):
    with pytest.raises(RuntimeError, match="exit code 3: step 12: particle 7 left the grid"):
        study_cases.run_case(failing_exe, study_cases.column_case(4, "linear", "USF"),
                             tmp_path)
    row = study_cases.run_column(failing_exe, 4, "linear", "USF", tmp_path)
    assert row["status"] == "failed" and "particle 7 left the grid" in row["note"]
    log_path = tmp_path / "runs.csv"
    log = study_cases.CsvLog(log_path, study_cases.COLUMN_FIELDS)
    log.write(row)
    log.close()
    rows = study_report.load_runs(log_path)
    assert rows[0]["status"] == "failed" and math.isnan(rows[0]["error"])
