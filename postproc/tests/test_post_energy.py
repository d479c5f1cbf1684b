"""mpm_post.energy: the energy drift and the energy plot."""

import numpy as np
import pytest
from matplotlib.image import imread

from mpm_post import energy, load_history, plot_energy
from mpm_post.energy import describe_drift, energy_balance, energy_columns, plot_run_energy


def history_of(total, potential=None):
    n = len(total)
    history = {"time": np.linspace(0.0, 1.0, n), "total": np.array(total, float)}
    if potential is not None:
        history["potential_energy"] = np.array(potential, float)
    return history


def test_balance_of_a_conserving_run_has_no_drift():
    balance = energy_balance(history_of([5.0, 4.0, 5.0], [0.0, -3.0, -5.0]))
    assert balance.drift == 0.0
    assert balance.gravity_work == 5.0 and balance.drift_of_gravity_work == 0.0
    assert (balance.start, balance.end) == (0.0, 1.0)


def test_drift_is_the_end_minus_the_start():
    # a loss of 1.5 in the middle does not count: the drift is what is left unaccounted for
    # at the end, +0.5 J of 4 J of gravity work
    balance = energy_balance(history_of([10.0, 8.5, 10.5], [0.0, -2.0, -4.0]))
    assert balance.drift == 0.5 and balance.gravity_work == 4.0
    assert balance.drift_of_gravity_work == 0.125
    assert describe_drift(balance, "J") == (
        "+0.5 J (total at the end - total at the start: energy not accounted for; "
        "12.5 % of the work of gravity, 4 J)")


def test_drift_from_history_file(make_run):
    # mpm_post_fakerun.history_rows: total drifts by 0.1 J per row (0.4 J after 4 rows), the
    # potential energy falls by 1 J per row (4 J of work of gravity)
    balance = energy_balance(load_history(make_run()))
    assert balance.drift == pytest.approx(0.4, rel=1e-12)
    assert balance.gravity_work == pytest.approx(4.0, rel=1e-12)


def test_columns_are_found_by_name_not_position(tmp_path):
    path = tmp_path / "history.csv"
    path.write_text("step,total,time,potential_energy\n0,2.0,0.0,0.0\n5,2.5,0.1,-10.0\n")
    balance = energy_balance(load_history(path))
    assert (balance.drift, balance.gravity_work, balance.end) == (0.5, 10.0, 0.1)


def test_drift_is_compared_with_the_work_of_gravity_and_loads():
    # a loaded run (history.csv's load_work): 2 J of gravity and 3 J of loads supplied
    history = history_of([10.0, 10.5], [0.0, -2.0])
    history["load_work"] = np.array([1.0, 4.0])
    balance = energy_balance(history)
    assert balance.load_work == 3.0 and balance.supplied == 5.0
    assert describe_drift(balance, "J").endswith("10 % of the work of gravity and loads, 5 J)")
    # loads only (no gravity): the share of the work of the loads
    history["potential_energy"] = np.zeros(2)
    assert describe_drift(energy_balance(history), "J").endswith(
        "16.7 % of the work of the loads, 3 J)")


def test_drift_without_gravity_work_says_so():
    assert describe_drift(energy_balance(history_of([1.0, 1.5])), "J/m") == (
        "+0.5 J/m (total at the end - total at the start: energy not accounted for; "
        "no potential_energy column to compare with the work of gravity)")
    balance = energy_balance(history_of([1.0, 0.75], [0.0, 0.0]))
    assert np.isnan(balance.drift_of_gravity_work)
    assert describe_drift(balance).endswith("; the work of gravity is 0 J, not positive)")
    assert describe_drift(balance).startswith("-0.25 J (")


def test_drift_of_empty_history():
    with pytest.raises(ValueError, match="empty"):
        energy_balance(history_of([]))


def test_drift_needs_the_total():
    with pytest.raises(KeyError, match="no 'total' column"):
        energy_balance({"time": np.zeros(2), "kinetic_energy": np.zeros(2)})


def test_energy_columns_follow_the_header():
    history = {"time": 0, "step": 0, "contact_work": 0, "total": 0, "kinetic_energy": 0}
    assert energy_columns(history) == [("kinetic_energy", "kinetic"), ("total", "total"),
                                       ("contact_work", "contact work")]


def test_plot_run_energy_titles_with_the_case_and_the_drift(make_run, tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(energy, "plot_energy",
                        lambda history, path, **options: calls.append(options) or path)
    path, drift = plot_run_energy(make_run(name="column"), tmp_path / "e.png")
    assert path == tmp_path / "e.png"
    assert drift.startswith("+0.4 J/m (total at the end - total at the start")
    assert calls == [{"title": "column\nenergy drift +0.4 J/m = total at t = 0.4 s - total at "
                               "t = 0 s\n(10 % of the work of gravity, 4 J/m)", "unit": "J/m"}]


def test_plot_energy_writes_image(make_run, tmp_path):
    out = tmp_path / "figs" / "sub" / "energy.png"  # parent folders do not exist yet
    path = plot_energy(load_history(make_run()), out)
    assert path == out
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = imread(out)
    assert image.shape[0] > 100 and image.shape[1] > 100
    assert image[..., :3].std() > 0.01  # something was drawn, not a blank canvas


def test_plot_energy_partial_columns(tmp_path):
    history = {"time": np.array([0.0, 1.0]), "total": np.array([1.0, 1.0])}
    assert plot_energy(history, tmp_path / "total.png").is_file()


def test_plot_energy_without_energy_columns(tmp_path):
    with pytest.raises(KeyError, match="no energy column"):
        plot_energy({"time": np.array([0.0, 1.0])}, tmp_path / "none.png")
    assert not (tmp_path / "none.png").exists()


def closed_history():
    """A history of the closed balance (docs/output.md): 2 J of gravity work, 1.75 J stored
    and dissipated, 0.25 J lost by the discretisation."""
    t = np.linspace(0.0, 1.0, 5)
    history = {"time": t, "step": np.arange(5.0), "kinetic_energy": 0.5 * t,
               "elastic_energy": 0.5 * t, "potential_energy": -2.0 * t,
               "plastic_work": 0.25 * t, "viscous_work": 0 * t, "damping_work": 0 * t,
               "friction_work": 0.25 * t, "load_work": 0 * t, "boundary_work": 0.125 * t,
               "transfer_loss": 0.125 * t}
    history["total"] = (history["kinetic_energy"] + history["elastic_energy"]
                        + history["potential_energy"] + history["plastic_work"]
                        + history["friction_work"] + history["boundary_work"]
                        + history["transfer_loss"])
    history["residual"] = history["total"] - history["total"][0]
    return history


def test_closed_balance_terms_have_their_names():
    labels = dict(energy_columns(closed_history()))
    assert labels["elastic_energy"] == "elastic (stored)"
    assert labels["plastic_work"] == "plastic dissipation"
    assert labels["friction_work"] == "friction work"
    assert labels["boundary_work"] == "stopped by fixed faces and contacts"
    assert labels["transfer_loss"] == "lost in particle-grid transfers"
    assert labels["residual"] == "residual"


def test_closed_balance_is_plotted_stacked_with_the_residual(tmp_path, monkeypatch):
    calls = {}
    real = energy._plot_stacked

    def spy(history, time, path, title, unit):
        calls["stacked"] = True
        return real(history, time, path, title, unit)

    monkeypatch.setattr(energy, "_plot_stacked", spy)
    path = plot_energy(closed_history(), tmp_path / "e.png")
    assert calls == {"stacked": True}
    assert {"boundary_work", "transfer_loss"} <= set(energy.STACKED_TERMS)
    image = imread(path)
    assert image.shape[0] > 100 and image.std() > 0.0
