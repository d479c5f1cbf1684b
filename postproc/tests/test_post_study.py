"""Tests of mpm_post.study: orders, Pareto fronts, recommendations, CSV reading, plots."""

import math

import pytest

from mpm_post.study import (cheapest_for, combos, load_study, observed_order, pareto_front,
                            plot_study)

HEADER = ("problem,amplitude,shape,scheme,cells,particles,steps,wall_s,error_l2_m,error_max_m,"
          "status\n")


def test_observed_order_of_exact_power_laws():
    cells = [8, 16, 32, 64]
    assert observed_order(cells, [1.0 / c**2 for c in cells]) == pytest.approx(2.0)
    assert observed_order(cells, [3.0 / c for c in cells]) == pytest.approx(1.0)
    # only the finest three count: a pre-asymptotic first point does not move the slope
    assert observed_order(cells, [1.0, 1.0 / 16**2, 1.0 / 32**2, 1.0 / 64**2]) == \
        pytest.approx(2.0)


def test_observed_order_needs_two_finite_points():
    assert math.isnan(observed_order([8, 16], [1e-3, math.nan]))
    assert math.isnan(observed_order([8], [1e-3]))


def test_pareto_front_keeps_only_undominated_points():
    points = [(1.0, 1e-2), (2.0, 1e-3), (3.0, 2e-3), (4.0, 1e-4), (0.5, 5e-2)]
    assert pareto_front(points) == [4, 0, 1, 3]


def test_cheapest_for_a_target():
    rows = [{"status": "ok", "error_l2_m": 1e-3, "wall_s": 1.0, "name": "a"},
            {"status": "ok", "error_l2_m": 1e-4, "wall_s": 5.0, "name": "b"},
            {"status": "ok", "error_l2_m": 5e-5, "wall_s": 3.0, "name": "c"},
            {"status": "failed", "error_l2_m": math.nan, "wall_s": math.nan, "name": "d"}]
    assert cheapest_for(rows, 1e-3)["name"] == "a"
    assert cheapest_for(rows, 1e-4)["name"] == "c"
    assert cheapest_for(rows, 1e-6) is None


def test_load_study_and_plot(tmp_path):
    path = tmp_path / "study.csv"
    lines = [HEADER]
    for shape in ("linear", "cpgimp"):
        for cells in (8, 16, 32):
            error = (1.0 / cells**2) if shape == "cpgimp" else 1e-2
            lines.append(f"mms,5.0E-02,{shape},MUSL,{cells},{2 * cells},{10 * cells},"
                         f"{1e-3 * cells:.6e},{error:.6e},{2 * error:.6e},ok\n")
    lines.append("mms,5.0E-02,linear,USL,128,,,,,,failed\n")
    path.write_text("".join(lines))
    rows = load_study(path)
    assert len(rows) == 7
    assert combos(rows) == [("linear", "MUSL"), ("cpgimp", "MUSL"), ("linear", "USL")]
    assert rows[-1]["status"] == "failed" and math.isnan(rows[-1]["wall_s"])
    png = tmp_path / "figs" / "study.png"
    plot_study(rows, png, "test")
    assert png.stat().st_size > 1000


def test_load_study_refuses_an_empty_file(tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text(HEADER)
    with pytest.raises(ValueError, match="no study rows"):
        load_study(path)
