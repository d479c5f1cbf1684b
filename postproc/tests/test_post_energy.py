"""mpm_post.energy: drift measure and energy plot."""

import numpy as np
import pytest
from matplotlib.image import imread

from mpm_post import energy_drift, load_history, plot_energy


def history_of(total, kinetic, strain):
    n = len(total)
    return {"time": np.linspace(0.0, 1.0, n), "kinetic_energy": np.array(kinetic, float),
            "strain_energy": np.array(strain, float), "total": np.array(total, float)}


def test_drift_of_conserving_run_is_zero():
    assert energy_drift(history_of([5.0, 5.0, 5.0], [5.0, 2.0, 0.0], [0.0, 3.0, 5.0])) == 0.0


def test_drift_value():
    # Largest |total - total[0]| is 1.5, a loss in the middle row (the last row gains only
    # 0.5); largest kinetic + strain is 20.
    history = history_of([10.0, 8.5, 10.5], [10.0, 15.0, 5.0], [0.0, 5.0, 4.0])
    assert energy_drift(history) == pytest.approx(1.5 / 20.0, rel=1e-15)


def test_drift_from_history_file(make_run):
    # conftest.history_rows: total drifts by 0.1 J per row (0.4 J after 4 rows); kinetic +
    # strain is 10 J in every row.
    assert energy_drift(load_history(make_run())) == pytest.approx(0.04, rel=1e-12)


def test_drift_without_mechanical_energy_is_finite():
    drift = energy_drift(history_of([0.0, 1e-300], [0.0, 0.0], [0.0, 0.0]))
    assert np.isfinite(drift) and drift > 0.0


def test_drift_of_empty_history():
    with pytest.raises(ValueError, match="empty"):
        energy_drift(history_of([], [], []))


def test_drift_needs_columns():
    with pytest.raises(KeyError, match="strain_energy"):
        energy_drift({"time": np.zeros(2), "kinetic_energy": np.zeros(2), "total": np.zeros(2)})


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
