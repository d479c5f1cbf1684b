"""mpm_post.plots, fit_order and pareto_front, and `python -m mpm_post plot ...`."""

import io
import math

import numpy as np
import pytest
from matplotlib.image import imread
from mpm_post_fakerun import write_geostatic_run, write_output

from mpm_post.cli import main
from mpm_post.plots import (load_convergence, load_costs, plot_convergence,
                            plot_error_vs_time, plot_profile)
from mpm_post.study import fit_order, observed_order, pareto_front

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def assert_png(path):
    """A PNG image with something drawn on it."""
    assert path.is_file() and path.read_bytes()[:8] == PNG_SIGNATURE
    image = imread(path)
    assert image.shape[0] > 100 and image.shape[1] > 100
    assert image[..., :3].std() > 0.01


# --- fit_order ----------------------------------------------------------------------------

def test_fit_order_of_exact_power_laws():
    h = np.array([0.1, 0.05, 0.025, 0.0125])
    for order, constant in [(2.0, 3.0), (1.0, 0.2), (0.5, 1e-4)]:
        slope, sigma = fit_order(h, constant * h**order)
        assert slope == pytest.approx(order, rel=1e-12)
        assert sigma < 1e-12        # a perfect line: no residual


def test_fit_order_standard_error_by_hand():
    # log h = -1, 0, 1; residuals d, -2d, d about the line (orthogonal to 1 and log h, so the
    # fit keeps the slope): sum of squares 6 d^2, n - 2 = 1, sum (log h - mean)^2 = 2, so the
    # standard error is sqrt(6 d^2 / 1 / 2) = sqrt(3) d.
    d, order = 0.05, 1.7
    log_h = np.array([-1.0, 0.0, 1.0])
    log_e = order * log_h + np.array([d, -2.0 * d, d]) - 4.0
    slope, sigma = fit_order(np.exp(log_h), np.exp(log_e))
    assert slope == pytest.approx(order, rel=1e-12)
    assert sigma == pytest.approx(math.sqrt(3.0) * d, rel=1e-10)


def test_fit_order_few_and_bad_points():
    slope, sigma = fit_order([0.1, 0.05], [4e-2, 1e-2])
    assert slope == pytest.approx(2.0, rel=1e-12) and math.isnan(sigma)
    # failed runs (nan), zero errors and bad cell sizes are left out
    slope, _ = fit_order([0.1, 0.05, 0.025, 0.0, 0.01],
                         [4e-2, 1e-2, 2.5e-3 * (1.0 + 1e-15), 1.0, math.nan])
    assert slope == pytest.approx(2.0, rel=1e-9)
    with pytest.raises(ValueError, match="at least two points"):
        fit_order([0.1, 0.05], [1e-2, 0.0])
    with pytest.raises(ValueError, match="at least two points"):
        fit_order([0.1, 0.1], [1e-2, 2e-2])
    with pytest.raises(ValueError, match="3 resolutions but 2 errors"):
        fit_order([0.1, 0.05, 0.02], [1e-2, 2e-2])


def test_observed_order_is_the_fit_over_cells():
    cells = [8, 16, 32, 64]
    errors = [1e-2, 3e-3, 7e-4, 2e-4]
    assert observed_order(cells, errors) == pytest.approx(
        -fit_order(cells[1:], errors[1:])[0], rel=1e-15)
    assert observed_order(cells, errors) == pytest.approx(
        fit_order(1.0 / np.array(cells[1:]), errors[1:])[0], rel=1e-12)
    assert math.isnan(observed_order([16, 16], [1e-3, 2e-3]))


# --- pareto_front -------------------------------------------------------------------------

def test_pareto_front_by_hand():
    # (time, error): 1 beats 2 in both; 3 is dominated by 0 only in time; 4 is the slowest but
    # the most accurate; 5 ties 0 in time with a larger error; 6 ties 1 in error, slower.
    points = [(1.0, 1e-2), (2.0, 1e-3), (3.0, 2e-3), (0.5, 5e-2), (8.0, 1e-5), (1.0, 2e-2),
              (2.5, 1e-3)]
    assert pareto_front(points) == [3, 0, 1, 4]


def test_pareto_front_leaves_out_failed_runs():
    points = [(1.0, math.nan), (2.0, 1e-3), (math.inf, 1e-9), (3.0, 1e-4)]
    assert pareto_front(points) == [1, 3]
    assert pareto_front([]) == []


def test_pareto_front_is_undominated_on_random_points():
    rng = np.random.default_rng(7)
    points = [tuple(p) for p in rng.uniform(0.0, 1.0, (40, 2))]
    front = set(pareto_front(points))
    for i, (cost, error) in enumerate(points):
        dominated = any(c <= cost and e <= error and (c, e) != (cost, error) for c, e in points)
        assert (i in front) == (not dominated)


# --- tables -------------------------------------------------------------------------------

def test_load_convergence_with_and_without_header(tmp_path):
    path = tmp_path / "conv.csv"
    path.write_text("h,error,label\n# a comment\n0.1,4e-2,cpgimp\n\n0.05, 1e-2 ,cpgimp\n"
                    "0.1,3e-2,linear\n")
    h, error, labels = load_convergence(path)
    assert h.tolist() == [0.1, 0.05, 0.1] and error.tolist() == [4e-2, 1e-2, 3e-2]
    assert labels == ["cpgimp", "cpgimp", "linear"]
    path.write_text("0.1,4e-2\n0.05,1e-2\n")      # no header, no label
    h, error, labels = load_convergence(path)
    assert h.tolist() == [0.1, 0.05] and labels == ["", ""]


def test_load_costs(tmp_path):
    path = tmp_path / "cost.csv"
    path.write_text("label,error,wall_time\nlinear MUSL,1e-2,0.5\ncpgimp MUSL,1e-3,2\n")
    labels, error, wall = load_costs(path)
    assert labels == ["linear MUSL", "cpgimp MUSL"]
    assert error.tolist() == [1e-2, 1e-3] and wall.tolist() == [0.5, 2.0]


@pytest.mark.parametrize("text,message", [
    ("h,error\n", "no data row"),
    ("0.1\n", "conv.csv:1: expected the columns h,error,label"),
    ("0.1,1e-2\n0.05,abc\n", "conv.csv:2: error 'abc' is not a number"),
    ("0.1,1e-2,a,b\n", "got 4 fields"),
])
def test_load_convergence_errors(tmp_path, text, message):
    path = tmp_path / "conv.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        load_convergence(path)


def test_load_table_missing(tmp_path):
    with pytest.raises(FileNotFoundError, match="table not found: .*none.csv"):
        load_costs(tmp_path / "none.csv")


# --- figures ------------------------------------------------------------------------------

def test_plot_convergence(tmp_path):
    h = np.array([0.1, 0.05, 0.025, 0.1, 0.05, 0.02])
    errors = np.concatenate([2.0 * h[:3] ** 2, [0.3, 0.15, math.nan]])
    labels = ["A"] * 3 + ["B"] * 3
    path, orders = plot_convergence(tmp_path / "figs" / "conv.png", h, errors, labels,
                                    slopes=(1, 2, 3), title="test")
    assert_png(path)
    assert orders["A"][0] == pytest.approx(2.0, rel=1e-12)
    assert orders["B"][0] == pytest.approx(1.0, rel=1e-12) and math.isnan(orders["B"][1])
    _, orders = plot_convergence(tmp_path / "one.png", [0.1], [1e-2])
    assert math.isnan(orders[""][0])
    with pytest.raises(ValueError, match="no point"):
        plot_convergence(tmp_path / "none.png", [0.1], [0.0])
    assert not (tmp_path / "none.png").exists()


def test_plot_error_vs_time(tmp_path):
    labels = ["a", "a", "b", "b", "c"]
    errors = np.array([1e-2, 1e-3, 5e-3, 1e-4, math.nan])
    wall = np.array([1.0, 10.0, 0.5, 100.0, 0.1])
    path, front = plot_error_vs_time(tmp_path / "cost.png", labels, errors, wall)
    assert_png(path)
    assert front == [2, 1, 3]      # indices into the input, the failed run c left out
    with pytest.raises(ValueError, match="2 errors but 1 run times"):
        plot_error_vs_time(tmp_path / "x.png", ["a", "b"], [1.0, 2.0], [1.0])


def test_plot_profile(tmp_path):
    x = np.linspace(0.005, 0.195, 20)
    path = plot_profile(tmp_path / "profile.png", x, 0.1 - 0.5 * x,
                        reference=([0.0, 0.2], [0.1, 0.0]), particles=(x, 0.05 - 0.25 * x),
                        toe=0.2)
    assert_png(path)


# --- python -m mpm_post plot / profile -----------------------------------------------------

def run(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_cli_plot_convergence_and_cost(tmp_path, capsys):
    table = tmp_path / "conv.csv"
    table.write_text("h,error,label\n0.1,2e-2,a\n0.05,5e-3,a\n0.025,1.25e-3,a\n")
    out_file = tmp_path / "figs" / "conv.png"
    code, out, err = run(["plot", "convergence", str(table), "--out", str(out_file),
                          "--slopes", "2"], capsys)
    assert code == 0, err
    assert_png(out_file)
    assert f"wrote {out_file}" in out and "a: order 2.000 +- 0.000 (3 points)" in out
    table = tmp_path / "cost.csv"
    table.write_text("a,1e-2,1\na,1e-3,10\nb,5e-3,20\n")
    out_file = tmp_path / "cost.png"
    code, out, err = run(["plot", "cost", str(table), "--out", str(out_file)], capsys)
    assert code == 0, err
    assert_png(out_file)
    assert "Pareto front (label, error, run time [s]):\n  a, 0.01, 1\n  a, 0.001, 10\n" in out


def test_cli_plot_energy_and_profile(tmp_path, capsys):
    run_dir = write_geostatic_run(tmp_path / "run")
    out_file = tmp_path / "energy.png"
    code, out, err = run(["plot", "energy", str(run_dir), "--out", str(out_file)], capsys)
    assert code == 0, err
    assert_png(out_file)
    reference = tmp_path / "ref.txt"
    reference.write_text("0.0 0.1\n0.05 0.1\n0.1 0.0\n")
    out_file = tmp_path / "profile.png"
    code, out, err = run(["plot", "profile", str(run_dir), "--reference", str(reference),
                          "--out", str(out_file), "--half-size", "0.0125"], capsys)
    assert code == 0, err
    assert_png(out_file)


def test_cli_plot_errors(tmp_path, capsys):
    code, _, err = run(["plot", "cost", str(tmp_path / "none.csv"),
                        "--out", str(tmp_path / "x.png")], capsys)
    assert code == 1 and "table not found" in err
    bad = tmp_path / "bad.csv"
    bad.write_text("0.1,x\n")
    code, _, err = run(["plot", "convergence", str(bad), "--out", str(tmp_path / "x.png")],
                       capsys)
    assert code == 1 and "bad.csv:1: error 'x' is not a number" in err
    assert not (tmp_path / "x.png").exists()
    code, _, err = run(["plot", "energy", str(tmp_path / "no_run"),
                        "--out", str(tmp_path / "x.png")], capsys)
    assert code == 1 and "history file not found" in err
    with pytest.raises(SystemExit) as info:
        main(["plot"])
    assert info.value.code == 2
    with pytest.raises(SystemExit) as info:
        main(["plot", "histogram", "x"])
    assert info.value.code == 2


def test_cli_profile_runout_and_heights(tmp_path, capsys):
    """A 0.2 x 0.1 m block that spreads into a 0.3 x 0.05 m layer; one stray particle."""
    spacing = 0.01

    def block(width, height):
        xs = (np.arange(round(width / spacing)) + 0.5) * spacing
        ys = (np.arange(round(height / spacing)) + 0.5) * spacing
        x, y = np.meshgrid(xs, ys, indexing="ij")
        return x.ravel(), y.ravel()

    run_dir = tmp_path / "collapse"
    run_dir.mkdir()
    for index, (time, (x, y)) in enumerate([(0.0, block(0.2, 0.1)), (1.0, block(0.3, 0.05))]):
        if index == 1:     # thrown ahead and up: counts neither in the toe nor in the height
            x, y = np.append(x, 0.6), np.append(y, 0.2)
        position = np.zeros((x.size, 3))
        position[:, 0], position[:, 1] = x, y
        write_output(run_dir / f"particles_{index:06d}.h5", time, index, 2,
                     {"position": position, "volume": np.full(x.size, spacing**2)})
    code, out, err = run(["profile", str(run_dir)], capsys)
    assert code == 0, err
    assert "toe [m]: 0.3\n" in out
    assert "height at wall [m]: 0.05\n" in out
    assert "max height [m]: 0.05\n" in out
    assert "runout from t = 0 s [m]: 0.1 (toe then 0.2)\n" in out
    code, out, _ = run(["profile", str(run_dir), "--time", "0"], capsys)
    assert code == 0 and "max height [m]: 0.1\n" in out and "runout from" not in out
    late = tmp_path / "late.png"
    for command in (["profile", str(run_dir)], ["plot", "profile", str(run_dir), "--out",
                                                str(late)]):
        code, out, err = run(command + ["--time", "2"], capsys)
        assert code == 2 and out == "" and "no output at time 2 s" in err
        assert "it is after the last output (the outputs run from 0 to 1 s" in err
    assert not late.exists()


def footing_history(tmp_path, names=("footing",)):
    """A history.csv with the reaction and displacement columns of prescribed_motion regions:
    the region moves down 1 mm per line and the material pushes back 100 N/m per mm."""
    header = "time,step,kinetic_energy,total,residual"
    for name in names:
        header += f",reaction_{name}_x,reaction_{name}_y"
    for name in names:
        header += f",displacement_{name}_x,displacement_{name}_y"
    rows = [header]
    for k in range(4):
        values = [0.1 * k, k, 0.0, 0.0, 0.0]
        values += [0.0, -100.0 * k] * len(names)
        values += [0.0, -0.001 * k] * len(names)
        rows.append(",".join(str(v) for v in values))
    path = tmp_path / "history.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def test_load_displacement_of_a_region(tmp_path):
    from mpm_post import load_history
    from mpm_post.plots import load_displacement, plot_load_displacement, region_names

    history = load_history(footing_history(tmp_path))
    assert region_names(history) == ["footing"]
    displacement, load, region, axis = load_displacement(history)
    assert (region, axis) == ("footing", "y")
    assert np.allclose(displacement, [0.0, 0.001, 0.002, 0.003])
    assert np.allclose(load, [0.0, 100.0, 200.0, 300.0])
    _, pressure, _, _ = load_displacement(history, width=0.5)
    assert np.allclose(pressure, 2.0 * load)
    path = plot_load_displacement(tmp_path / "ld.png", displacement, load,
                                  reference=(250.0, "limit"))
    assert imread(path).shape[0] > 100


def test_load_displacement_refuses_what_the_history_lacks(tmp_path):
    from mpm_post import load_history
    from mpm_post.plots import load_displacement

    history = load_history(footing_history(tmp_path, names=("a", "b")))
    with pytest.raises(ValueError, match="several regions"):
        load_displacement(history)
    with pytest.raises(ValueError, match="no region 'c'"):
        load_displacement(history, region="c")
    history.pop("displacement_a_x")
    history.pop("displacement_b_x")
    with pytest.raises(ValueError, match="no prescribed_motion region"):
        load_displacement(history)


def test_load_displacement_command(tmp_path):
    out = io.StringIO()
    assert main(["plot", "load-displacement", str(footing_history(tmp_path)), "--out",
                 str(tmp_path / "f.png")], out=out) == 0
    assert "largest load 300 N (N/m in 2D) at displacement 0.003 m" in out.getvalue()
    assert (tmp_path / "f.png").is_file()


# --- strength reduction ---------------------------------------------------------------------

def strength_reduction_table(tmp_path, rows):
    path = tmp_path / "strength_reduction.csv"
    lines = ["trial,factor,displacement,kinetic_ratio,fails,folder"]
    lines += [f"{k + 1},{f},{u},1e-7,{int(fails)},{tmp_path}/trial_{k + 1}"
              for k, (f, u, fails) in enumerate(rows)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_strength_reduction_table_sorted_and_bracket(tmp_path):
    from mpm_post.plots import factor_of_safety, load_strength_reduction
    strength_reduction_table(tmp_path, [(1.0, 0.003, False), (2.0, 5.5, True),
                                        (1.5, 0.18, True), (1.25, 0.006, False)])
    trials = load_strength_reduction(tmp_path)
    assert list(trials["factor"]) == [1.0, 1.25, 1.5, 2.0]
    assert list(trials["fails"]) == [False, False, True, True]
    assert factor_of_safety(trials) == (1.25, 1.5)


def test_strength_reduction_command(tmp_path):
    strength_reduction_table(tmp_path, [(1.0, 0.003, False), (2.0, 5.5, True),
                                        (1.5, 0.18, True), (1.25, 0.006, False)])
    out = io.StringIO()
    assert main(["plot", "strength-reduction", str(tmp_path), "--limit", "0.1", "--reference",
                 "1.4", "--out", str(tmp_path / "s.png")], out=out) == 0
    assert "factor of safety 1.375 (holds at 1.25, fails at 1.5; 4 trials)" in out.getvalue()
    assert_png(tmp_path / "s.png")


def test_strength_reduction_command_outside_bracket(tmp_path):
    strength_reduction_table(tmp_path, [(1.0, 0.003, False), (1.2, 0.005, False)])
    out = io.StringIO()
    assert main(["plot", "strength-reduction", str(tmp_path / "strength_reduction.csv"),
                 "--out", str(tmp_path / "s.png")], out=out) == 0
    assert "holds at every factor tried (up to 1.2)" in out.getvalue()


def test_strength_reduction_command_not_a_table(tmp_path):
    (tmp_path / "strength_reduction.csv").write_text("time,kinetic_energy\n0,1\n")
    err = io.StringIO()
    import contextlib
    with contextlib.redirect_stderr(err):
        assert main(["plot", "strength-reduction", str(tmp_path), "--out",
                     str(tmp_path / "s.png")], out=io.StringIO()) == 1
    assert "not a strength_reduction.csv" in err.getvalue()
