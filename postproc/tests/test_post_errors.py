"""mpm_post.errors and `python -m mpm_post error`: norms, safe expressions, exit codes."""

import math
import os
import subprocess
import sys
import time

import numpy as np
import pytest
from mpm_post_fakerun import (COLUMN_X, COLUMN_Y, G, GEOSTATIC, HEIGHT, MASSES, OFFSETS,
                              POSTPROC, RHO, SHIFT, write_geostatic_run)

from mpm_post import load_particles, output_at
from mpm_post.cli import main
from mpm_post.errors import (ErrorNorms, ExpressionError, compile_expression, error_norms,
                             exact_values, field_component, particle_error)

# Hand values of the norms of OFFSETS = [1, -2, 0.5, 0] Pa:
# mass weights [1, 1, 2, 4] (sum 8): L1 = (1 + 2 + 1 + 0) / 8, L2 = sqrt((1 + 4 + 0.5) / 8);
# equal weights (volumes, or none): L1 = 3.5 / 4, L2 = sqrt(5.25 / 4); Linf = 2 for all.
L1_MASS, L2_MASS = 0.5, math.sqrt(0.6875)
L1_EQUAL, L2_EQUAL = 0.875, math.sqrt(1.3125)
LINF = 2.0
SCALE = RHO * G * (HEIGHT - COLUMN_Y[0])     # max |exact|: at the lowest particle [Pa]
# Sums of four terms of order 1 Pa against a stress of 2.3e3 Pa evaluated in two ways: the
# difference carries the round-off of the stress values, a few ulp of 2.3e3.
ROUND_OFF = 1e-11


def positions(*columns):
    """(n, 3) positions from x and y columns (z = 0)."""
    x = np.asarray(columns[0], dtype=float)
    out = np.zeros((x.size, 3))
    for k, column in enumerate(columns):
        out[:, k] = column
    return out


# --- error_norms --------------------------------------------------------------------------

def test_norms_of_known_differences():
    exact = np.array([10.0, -20.0, 5.0, 40.0])
    values = exact + OFFSETS
    norms = error_norms(values, exact, weights=MASSES)
    assert norms.l1 == pytest.approx(L1_MASS, rel=1e-15)
    assert norms.l2 == pytest.approx(L2_MASS, rel=1e-15)
    assert norms.linf == LINF
    assert norms.scale == 40.0 and norms.count == 4
    assert norms.relative("l2") == pytest.approx(L2_MASS / 40.0, rel=1e-15)
    equal = error_norms(values, exact)
    assert (equal.l1, equal.l2) == pytest.approx((L1_EQUAL, L2_EQUAL), rel=1e-15)
    # weights matter only through their ratios
    scaled = error_norms(values, exact, weights=1e-3 * MASSES)
    assert scaled.l2 == pytest.approx(L2_MASS, rel=1e-14)


def test_norms_ordering_and_exact_match():
    rng = np.random.default_rng(3)
    exact = rng.normal(size=50)
    values = exact + rng.normal(scale=1e-2, size=50)
    norms = error_norms(values, exact, weights=rng.uniform(0.5, 2.0, 50))
    # weighted means: L1 <= L2 <= Linf (Jensen), and all positive
    assert 0.0 < norms.l1 <= norms.l2 <= norms.linf
    zero = error_norms(exact, exact)
    assert (zero.l1, zero.l2, zero.linf) == (0.0, 0.0, 0.0)


def test_norms_scale():
    norms = error_norms([1.0, 2.0], [0.0, 0.0], scale=4.0)
    assert norms.relative("linf") == 0.5
    assert math.isnan(error_norms([1.0], [0.0]).relative("l1"))   # exact field 0: no scale
    with pytest.raises(ValueError, match="unknown norm 'l3'"):
        norms.absolute("l3")
    assert isinstance(norms, ErrorNorms)


@pytest.mark.parametrize("values,exact,weights,scale,message", [
    ([1.0, 2.0], [1.0], None, None, "2 field values but 1 exact"),
    ([], [], None, None, "no particle"),
    ([1.0, 2.0], [1.0, 2.0], [1.0], None, "1 weights for 2 particles"),
    ([1.0, 2.0], [1.0, 2.0], [1.0, -1.0], None, "weights must be"),
    ([1.0, 2.0], [1.0, 2.0], [0.0, 0.0], None, "weights must be"),
    ([1.0, np.nan], [1.0, 2.0], None, None, "1 non-finite"),
    ([1.0, 2.0], [1.0, 2.0], None, 0.0, "scale must be a positive"),
])
def test_norms_refuse_bad_input(values, exact, weights, scale, message):
    with pytest.raises(ValueError, match=message):
        error_norms(values, exact, weights, scale)


# --- expressions --------------------------------------------------------------------------

X = positions([0.1, 0.4, 0.7], [0.2, 0.5, 0.9], [0.0, 1.0, 2.0])


@pytest.mark.parametrize("text,expected", [
    ("-2650*9.81*(0.1 - y)", -2650 * 9.81 * (0.1 - X[:, 1])),
    ("sin(pi*x)*exp(-t)", np.sin(np.pi * X[:, 0]) * np.exp(-0.5)),
    ("np.sqrt(x**2 + y**2)", np.hypot(X[:, 0], X[:, 1])),
    ("numpy.cos(z) + e", np.cos(X[:, 2]) + np.e),
    ("where(y > 0.3, 1, -1)", np.array([-1.0, 1.0, 1.0])),
    ("0.3 < y <= 0.9", np.array([0.0, 1.0, 1.0])),
    ("maximum(x, y) - minimum(x, y)", np.abs(X[:, 0] - X[:, 1])),
    ("x % 0.3 + x // 0.3", X[:, 0] % 0.3 + X[:, 0] // 0.3),
    ("-x + +y", X[:, 1] - X[:, 0]),
    ("2", np.full(3, 2.0)),
    ("t", np.full(3, 0.5)),
    ("1e-3*x", 1e-3 * X[:, 0]),
])
def test_expression_values(text, expected):
    np.testing.assert_allclose(exact_values(text, X, 0.5), expected, rtol=1e-15, atol=1e-15)


@pytest.mark.parametrize("text,message", [
    ("__import__('os').system('true')", "calling '__import__('os').system'"),
    ("__import__('os')", "unknown function '__import__'"),
    ("open('x')", "unknown function 'open'"),
    ("eval('1')", "unknown function 'eval'"),
    ("np.load('a.npy')", "unknown function 'load'"),
    ("np.linalg.norm(x)", "calling 'np.linalg.norm'"),
    ("x.__class__", "'x.__class__' at column 1 is not allowed"),
    ("().__class__.__base__", "is not allowed"),
    ("np.pi", "'np.pi' at column 1 is not allowed"),
    ("x[0]", "'x[0]' at column 1 is not allowed"),
    ("sin(x, out=y)", "a keyword argument"),
    ("sin(*x)", "a starred argument"),
    ("'abc'", "the constant 'abc'"),
    ("True", "the constant True"),
    ("1j*x", "the constant 1j"),
    ("lambda: 1", "is not allowed"),
    ("[x, y]", "is not allowed"),
    ("(a := 2)", "is not allowed"),
    ("x if y else z", "is not allowed"),
    ("x and y", "is not allowed"),
    ("not x", "the operator Not"),
    ("~x", "the operator Invert"),
    ("x @ y", "the operator MatMult"),
    ("x << 1", "the operator LShift"),
    ("x is y", "the comparison Is"),
    ("q*2", "unknown name 'q'"),
    ("sin", "a function name must be called"),
    ("x(1)", "unknown function 'x'"),
    ("1 +", "syntax error"),
    ("", "empty"),
    ("x" * 3000, "longer than 2000"),
    ("+".join(["x"] * 300), "nested more than 200"),
])
def test_expression_refused(text, message):
    with pytest.raises(ExpressionError) as info:
        compile_expression(text)
    assert message in str(info.value)


def test_refused_expression_does_nothing(tmp_path):
    """Refused at compile time, before any of it could run."""
    target = tmp_path / "written"
    for text in [f"open('{target}', 'w')", f"np.save('{target}', x)",
                 f"__import__('pathlib').Path('{target}').touch()"]:
        with pytest.raises(ExpressionError):
            compile_expression(text)
    assert not target.exists()


def test_runaway_power_is_float_and_fast():
    """Numbers are float64: 9**9**9**9 overflows to inf at once instead of a huge integer."""
    exact = compile_expression("9**9**9**9 + 0*x")
    start = time.perf_counter()
    values = exact(X, 0.0)
    assert time.perf_counter() - start < 1.0
    assert np.all(np.isinf(values))
    with pytest.raises(ValueError, match="not finite at 3 of 3 particles"):
        exact_values(exact, X, 0.0)


def test_exact_values_from_a_callable_and_its_checks():
    np.testing.assert_array_equal(exact_values(lambda x, t: 2.0 * x[:, 0] + t, X, 1.0),
                                  2.0 * X[:, 0] + 1.0)
    np.testing.assert_array_equal(exact_values(lambda x, t: 7.0, X, 0.0), np.full(3, 7.0))
    with pytest.raises(ValueError, match=r"shape \(2,\), expected \(3,\)"):
        exact_values(lambda x, t: np.zeros(2), X, 0.0)
    with pytest.raises(ValueError, match="first at x = 0.1, y = 0.2"):
        exact_values("log(x - 0.2)", X, 0.0)


# --- particle fields ----------------------------------------------------------------------

def test_field_component(tmp_path):
    data = load_particles(write_geostatic_run(tmp_path / "run"))
    np.testing.assert_array_equal(field_component(data, "stress", "yy"), data["stress"][:, 1])
    np.testing.assert_array_equal(field_component(data, "position", "x"), COLUMN_X + SHIFT)
    np.testing.assert_allclose(field_component(data, "velocity", "magnitude"), 0.5 * COLUMN_X,
                               rtol=1e-15)
    np.testing.assert_array_equal(field_component(data, "mass"), MASSES)
    with pytest.raises(KeyError, match="no field 'pressure'.*fields: displacement"):
        field_component(data, "pressure", None)
    with pytest.raises(KeyError, match=r"no component 'yz' for field 'stress' \(components: "
                                       r"xx, yy, zz, xy\)"):
        field_component(data, "stress", "yz")
    with pytest.raises(KeyError, match="no component given .*magnitude"):
        field_component(data, "velocity", None)
    with pytest.raises(KeyError, match="one value per particle"):
        field_component(data, "mass", "x")


@pytest.mark.parametrize("weight,l1,l2", [("mass", L1_MASS, L2_MASS),
                                          ("volume", L1_EQUAL, L2_EQUAL),
                                          ("none", L1_EQUAL, L2_EQUAL)])
def test_particle_error_of_the_geostatic_run(tmp_path, weight, l1, l2):
    data = load_particles(write_geostatic_run(tmp_path / "run"))
    # the stress error is independent of x, so the shifted current positions do not matter
    norms = particle_error(data, "stress", "yy", GEOSTATIC, weight=weight)
    assert (norms.l1, norms.l2, norms.linf) == pytest.approx((l1, l2, LINF), abs=ROUND_OFF)
    assert norms.scale == pytest.approx(SCALE, rel=1e-14)


def test_particle_error_coordinates_and_callables(tmp_path):
    run_dir = write_geostatic_run(tmp_path / "run", times=(0.0, 0.5))
    data = load_particles(run_dir)
    # velocity x = t * (initial x): exact at the initial positions, off by t * SHIFT at the
    # current ones
    initial = particle_error(data, "velocity", "x", "t*x", coordinates="initial")
    # position - displacement recovers x to an ulp of 0.09 m (1.4e-17), times t = 0.5 s
    assert initial.linf < 1e-16
    current = particle_error(data, "velocity", "x", lambda x, t: t * x[:, 0])
    assert current.l1 == pytest.approx(0.5 * SHIFT, rel=1e-12)
    assert current.linf == pytest.approx(0.5 * SHIFT, rel=1e-12)
    # the first output holds the exact stress
    first = particle_error(load_particles(run_dir, time=0.0), "stress", "yy", GEOSTATIC)
    assert first.linf < ROUND_OFF
    with pytest.raises(ValueError, match="coordinates"):
        particle_error(data, "velocity", "x", "x", coordinates="deformed")
    del data["displacement"]
    with pytest.raises(KeyError, match="initial positions are unknown"):
        particle_error(data, "velocity", "x", "x", coordinates="initial")
    del data["mass"]
    with pytest.raises(KeyError, match="no field 'mass' .* to weight"):
        particle_error(data, "velocity", "x", "x")


def test_output_at(tmp_path):
    run_dir = write_geostatic_run(tmp_path / "run", times=(0.0, 0.25, 0.5))
    assert output_at(run_dir)[0] == 0.5
    assert output_at(run_dir, 0.25)[1].name == "particles_000001.h5"
    assert output_at(run_dir, 0.2502)[0] == 0.25           # within 1e-3 * 0.5 s
    with pytest.raises(ValueError, match=r"no output at time 0.3 s .*output times \[s\]: "
                                         r"0 0.25 0.5; tolerance 0.0005 s"):
        output_at(run_dir, 0.3)
    assert output_at(run_dir, 0.3, tolerance=0.06)[0] == 0.25
    single = run_dir / "particles_000002.h5"
    assert output_at(single, 0.5) == (0.5, single)
    with pytest.raises(ValueError, match="no output at time 0"):
        output_at(single, 0.0)
    with pytest.raises(FileNotFoundError, match="no particles_NNNNNN.h5"):
        output_at(tmp_path)


# --- python -m mpm_post error -------------------------------------------------------------

def run(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def norm_rows(out):
    """{norm: (absolute, relative)} from the table the error command prints."""
    rows = {}
    for line in out.splitlines():
        parts = line.split()
        if parts and parts[0] in ("L1", "L2", "Linf"):
            rows[parts[0]] = (float(parts[1]), float(parts[2]))
    return rows


def test_cli_error_prints_the_norms(tmp_path, capsys):
    run_dir = write_geostatic_run(tmp_path / "run")
    # the expression starts with '-': given as a separate argument, as in the issue
    code, out, err = run(["error", str(run_dir), "--field", "stress", "--component", "yy",
                          "--exact", "-2650*9.81*(0.1-y)"], capsys)
    assert code == 0, err
    assert out.startswith("stress yy at time 0.5 s (step 100), 4 particles")
    assert "weights: mass" in out and "(max |exact|)" in out
    rows = norm_rows(out)
    assert list(rows) == ["L1", "L2", "Linf"]
    for name, value in [("L1", L1_MASS), ("L2", L2_MASS), ("Linf", LINF)]:
        assert rows[name][0] == pytest.approx(value, rel=1e-6)       # printed to 7 digits
        assert rows[name][1] == pytest.approx(value / SCALE, rel=1e-6)


def test_cli_error_options(tmp_path, capsys):
    run_dir = write_geostatic_run(tmp_path / "run")
    base = ["error", str(run_dir), "--field", "stress", "--component", "yy",
            f"--exact={GEOSTATIC}"]
    code, out, _ = run(base + ["--norm", "l2", "--weight", "volume", "--scale", "2"], capsys)
    assert code == 0
    assert norm_rows(out) == {"L2": pytest.approx((L2_EQUAL, L2_EQUAL / 2.0), rel=1e-6)}
    assert "(--scale)" in out
    code, out, _ = run(base + ["--time", "0"], capsys)
    assert code == 0 and norm_rows(out)["Linf"][0] < 1e-9
    code, out, _ = run(["error", str(run_dir), "--field", "velocity", "--component", "x",
                        "--exact", "t*x", "--coordinates", "initial"], capsys)
    assert code == 0 and norm_rows(out)["Linf"][0] < 1e-16     # as in the test above


@pytest.mark.parametrize("args,code,message", [
    (["--field", "pressure", "--exact", "0"], 1, "no field 'pressure'"),
    (["--field", "stress", "--component", "qq", "--exact", "0"], 1, "no component 'qq'"),
    (["--field", "stress", "--exact", "0"], 1, "no component given for field 'stress'"),
    (["--field", "stress", "--component", "yy", "--exact", "0", "--time", "0.3"], 1,
     "no output at time 0.3 s"),
    (["--field", "stress", "--component", "yy", "--exact", "0", "--time", "9"], 2,
     "no output at time 9 s in"),
    (["--field", "stress", "--component", "yy", "--exact", "1/(y - y)"], 1,
     "not finite at 4 of 4"),
    (["--field", "stress", "--component", "yy", "--exact", "__import__('os')"], 2,
     "unknown function '__import__'"),
    (["--field", "stress", "--component", "yy", "--exact", "-2650*g*(0.1-y)"], 2,
     "unknown name 'g'"),
    (["--field", "stress", "--component", "yy", "--exact", "(y"], 2, "syntax error"),
])
def test_cli_error_exit_codes(tmp_path, capsys, args, code, message):
    run_dir = write_geostatic_run(tmp_path / "run")
    result, out, err = run(["error", str(run_dir)] + args, capsys)
    assert result == code
    assert err.startswith("mpm_post: error: ") and message in err
    assert out == ""


def test_cli_error_time_tolerance(tmp_path, capsys):
    run_dir = write_geostatic_run(tmp_path / "run")
    code, out, err = run(["error", str(run_dir), "--field", "stress", "--component", "yy",
                          "--exact", "0", "--time", "0.45", "--time-tol", "0.1"], capsys)
    assert code == 0, err
    assert "at time 0.5 s" in out


def test_cli_error_checks_the_expression_before_the_run(tmp_path, capsys):
    code, _, err = run(["error", str(tmp_path / "missing"), "--field", "stress",
                        "--exact", "os.system('true')"], capsys)
    assert code == 2 and "calling 'os.system'" in err


@pytest.mark.parametrize("args", [["--scale", "0"], ["--norm", "l3"], ["--weight", "density"],
                                  ["--time-tol", "-1"]])
def test_cli_error_bad_options(tmp_path, capsys, args):
    with pytest.raises(SystemExit) as info:
        main(["error", str(tmp_path), "--field", "stress", "--exact", "0"] + args)
    assert info.value.code == 2
    assert "usage:" in capsys.readouterr().err


def test_cli_error_python_dash_m(tmp_path):
    """Exit codes of the real entry point, run as a user would."""
    run_dir = write_geostatic_run(tmp_path / "run")
    env = dict(os.environ, PYTHONPATH=str(POSTPROC))
    command = [sys.executable, "-m", "mpm_post", "error", str(run_dir), "--field", "stress",
               "--component", "yy", "--exact"]
    good = subprocess.run(command + ["-2650*9.81*(0.1-y)"], env=env, capture_output=True,
                          text=True, timeout=120, check=False)
    assert good.returncode == 0, good.stderr
    assert norm_rows(good.stdout)["Linf"][0] == pytest.approx(LINF, rel=1e-6)
    bad = subprocess.run(command + ["exec('1')"], env=env, capture_output=True, text=True,
                         timeout=120, check=False)
    assert bad.returncode == 2
    assert "unknown function 'exec'" in bad.stderr
