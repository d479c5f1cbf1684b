"""python -m mpm_post: summary, energy and field commands."""

import os
import subprocess
import sys

import numpy as np
import pytest
from mpm_post_fakerun import POSTPROC, particle_fields

from mpm_post.cli import main


def run(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_summary(make_run, capsys):
    run_dir = make_run(dim=3, times=(0.0, 0.25, 0.5), n=8, name="column")
    code, out, err = run(["summary", str(run_dir)], capsys)
    assert code == 0, err
    assert "outputs: 3" in out
    assert "times [s]: 0 0.25 0.5" in out
    assert "case: column" in out
    assert "dimension: 3" in out
    assert "particles: 8" in out
    assert "last output: step 20, time 0.5 s" in out
    assert "final kinetic energy [J]: 2.000000e+00" in out
    # mpm_post_fakerun.history_rows: the total grows by 0.4 J, gravity does 4 J of work
    assert ("energy drift: +0.4 J (total at the end - total at the start: energy not "
            "accounted for; 10 % of the work of gravity, 4 J)\n") in out


def test_summary_2d_energies_are_per_metre(make_run, capsys):
    code, out, err = run(["summary", str(make_run(dim=2))], capsys)
    assert code == 0, err
    assert "final kinetic energy [J/m]: 2.000000e+00" in out
    assert "energy drift: +0.4 J/m (" in out


def test_summary_without_a_total_column(make_run, capsys):
    run_dir = make_run(history=False)
    (run_dir / "history.csv").write_text("time,step,kinetic_energy\n0,0,1.0\n")
    code, out, err = run(["summary", str(run_dir)], capsys)
    assert code == 0, err
    assert ("energy drift: not available (history.csv has no 'total' column; columns: time, "
            "step, kinetic_energy)\n") in out


def test_summary_many_outputs_are_abbreviated(make_run, capsys):
    run_dir = make_run(times=tuple(0.1 * i for i in range(10)), history=False)
    code, out, _ = run(["summary", str(run_dir)], capsys)
    assert code == 0
    assert "outputs: 10" in out
    assert "times [s]: 0 0.1 0.2 ... 0.7 0.8 0.9" in out
    assert "history: no history.csv" in out


def test_summary_missing_run(tmp_path, capsys):
    code, out, err = run(["summary", str(tmp_path / "missing")], capsys)
    assert code == 1
    assert "mpm_post: error: run directory not found" in err
    assert out == ""


def test_energy_plot(make_run, tmp_path, capsys):
    out_file = tmp_path / "figs" / "energy.png"
    code, out, err = run(["energy", str(make_run()), "--out", str(out_file)], capsys)
    assert code == 0, err
    assert out_file.is_file() and out_file.stat().st_size > 1000
    assert str(out_file) in out


def test_energy_and_plot_energy_are_one_figure(make_run, tmp_path, capsys):
    """The README's 'energy' and 'plot energy' write the same image (title, drift) and text."""
    run_dir = make_run(name="column")
    outputs = []
    for command in (["energy"], ["plot", "energy"]):
        out_file = tmp_path / f"{len(outputs)}.png"
        code, out, err = run(command + [str(run_dir), "--out", str(out_file)], capsys)
        assert code == 0, err
        outputs.append((out_file.read_bytes(), out.replace(str(out_file), "PNG")))
    assert outputs[0] == outputs[1]
    assert outputs[0][1] == ("wrote PNG\nenergy drift: +0.4 J/m (total at the end - total at "
                             "the start: energy not accounted for; 10 % of the work of "
                             "gravity, 4 J/m)\n")


def test_energy_without_history(make_run, tmp_path, capsys):
    code, _, err = run(["energy", str(make_run(history=False)), "--out",
                        str(tmp_path / "e.png")], capsys)
    assert code == 1
    assert "history file not found" in err
    assert not (tmp_path / "e.png").exists()


def stats_rows(out):
    """{component: (min, max, mean)} from the field command's table."""
    rows = {}
    for line in out.splitlines()[2:]:
        label, *values = line.split()
        rows[label] = tuple(float(v) for v in values)
    return rows


@pytest.mark.parametrize("dim,labels", [(2, ["xx", "yy", "zz", "xy"]),
                                        (3, ["xx", "yy", "zz", "xy", "yz", "zx"])])
def test_field_stress_stats(make_run, capsys, dim, labels):
    run_dir = make_run(dim=dim, times=(0.0, 0.5, 1.0), n=8)
    code, out, err = run(["field", str(run_dir), "--field", "stress", "--time", "0.4"], capsys)
    assert code == 0, err
    assert out.startswith("stress at time 0.5 s (step 10), 8 particles")
    stress = particle_fields(dim, 8, 0.5)["stress"]
    rows = stats_rows(out)
    assert list(rows) == labels
    for k, label in enumerate(labels):
        np.testing.assert_allclose(rows[label], (stress[:, k].min(), stress[:, k].max(),
                                                 stress[:, k].mean()), rtol=1e-6)


def test_field_scalar_and_vector(make_run, capsys):
    run_dir = make_run(times=(0.0,), n=8)
    code, out, _ = run(["field", str(run_dir), "--field", "mass"], capsys)
    assert code == 0
    assert stats_rows(out) == {"mass": (2.5, 2.5, 2.5)}
    code, out, _ = run(["field", str(run_dir), "--field", "velocity"], capsys)
    assert code == 0
    assert list(stats_rows(out)) == ["x", "y", "z"]


@pytest.mark.parametrize("time,side", [("7", "after the last"), ("-1", "before the first")])
def test_field_time_outside_the_run(make_run, capsys, time, side):
    """A run that ends at t = 1 has no answer for t = 7: exit code 2, the times it has."""
    run_dir = make_run(times=(0.0, 0.5, 1.0))
    code, out, err = run(["field", str(run_dir), "--field", "stress", "--time", time], capsys)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1     # one line, no traceback
    assert err.startswith(f"mpm_post: error: no output at time {time} s in {run_dir}: it is "
                          f"{side} output (the outputs run from 0 to 1 s; output times [s]: "
                          "0 0.5 1)")


def test_field_unknown(make_run, capsys):
    code, _, err = run(["field", str(make_run()), "--field", "pressure"], capsys)
    assert code == 1
    assert "no field 'pressure'" in err
    assert "stress" in err and "velocity" in err


def test_bad_command_line(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["nonsense"])
    assert exit_info.value.code == 2


def test_python_dash_m(make_run):
    """The module entry point, run as a user would from the repository root."""
    env = dict(os.environ, PYTHONPATH=str(POSTPROC))
    result = subprocess.run([sys.executable, "-m", "mpm_post", "summary", str(make_run())],
                            env=env, capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    assert "outputs: 3" in result.stdout
    missing = subprocess.run([sys.executable, "-m", "mpm_post", "summary", "/nonexistent/run"],
                             env=env, capture_output=True, text=True, timeout=120, check=False)
    assert missing.returncode == 1
    assert "run directory not found" in missing.stderr
