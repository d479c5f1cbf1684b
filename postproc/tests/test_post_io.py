"""mpm_post.io on run directories written in the documented layout."""

import h5py
import numpy as np
import pytest
from mpm_post_fakerun import particle_fields, write_history, write_output

from mpm_post import list_outputs, load_grid, load_history, load_particles
from mpm_post.io import TimeOutsideRunError


# ----------------------------------------------------------------------------- list_outputs
def test_list_outputs_sorted_by_time_attribute(tmp_path):
    # Indices deliberately out of time order: the time comes from the attribute, not the name.
    for index, time in [(0, 0.5), (1, 0.0), (2, 0.25)]:
        write_output(tmp_path / f"particles_{index:06d}.h5", time, index, 2,
                     particle_fields(2, 3, time))
    outputs = list_outputs(tmp_path)
    assert [t for t, _ in outputs] == [0.0, 0.25, 0.5]
    assert [p.name for _, p in outputs] == [
        "particles_000001.h5", "particles_000002.h5", "particles_000000.h5"]


def test_list_outputs_ignores_other_files(make_run):
    run_dir = make_run(times=(0.0, 0.1))
    (run_dir / "case.xdmf").write_text("<Xdmf/>")
    (run_dir / "particles_1.h5").write_bytes(b"")  # not 6 digits
    (run_dir / "particles_000009.h5.tmp").write_bytes(b"")
    (run_dir / "particles_000007.h5").mkdir()  # a directory, not an output
    assert [p.name for _, p in list_outputs(run_dir)] == [
        "particles_000000.h5", "particles_000001.h5"]


def test_list_outputs_empty_directory(tmp_path):
    assert list_outputs(tmp_path) == []


def test_list_outputs_missing_directory(tmp_path):
    missing = tmp_path / "no_such_run"
    with pytest.raises(FileNotFoundError, match="run directory not found: .*no_such_run"):
        list_outputs(missing)


def test_list_outputs_on_a_file(tmp_path):
    path = tmp_path / "history.csv"
    path.write_text("time\n")
    with pytest.raises(NotADirectoryError, match="not a run directory"):
        list_outputs(path)


def test_list_outputs_missing_time_attribute(tmp_path):
    with h5py.File(tmp_path / "particles_000000.h5", "w") as h5file:
        h5file.create_group("particles").create_dataset("position", data=np.zeros((1, 3)))
    with pytest.raises(ValueError, match="attribute 'time' is missing"):
        list_outputs(tmp_path)


# ----------------------------------------------------------------------------- load_particles
@pytest.mark.parametrize("dim,nstress", [(2, 4), (3, 6)])
def test_load_particles_round_trip(make_run, dim, nstress):
    run_dir = make_run(dim=dim, times=(0.0, 0.25, 0.5), n=8)
    data = load_particles(run_dir)  # last output
    expected = particle_fields(dim, 8, 0.5)
    assert data["time"] == 0.5
    assert data["step"] == 20
    assert data["dimension"] == dim
    assert data["case_name"] == "case"
    assert data["path"].endswith("particles_000002.h5")
    assert data["stress"].shape == (8, nstress)
    for name, array in expected.items():
        np.testing.assert_array_equal(data[name], array, err_msg=name)
    if dim == 2:
        assert np.all(data["position"][:, 2] == 0.0)


@pytest.mark.parametrize("time,expected", [
    (None, 0.5), (0.0, 0.0), (0.1, 0.0), (0.13, 0.25), (0.26, 0.25), (0.49, 0.5),
    (0.5004, 0.5), (-0.0004, 0.0)])     # within 1e-3 of the last time (0.5 s) of either end
def test_load_particles_nearest_time(make_run, time, expected):
    run_dir = make_run(times=(0.0, 0.25, 0.5))
    data = load_particles(run_dir, time=time)
    assert data["time"] == expected
    np.testing.assert_array_equal(data["stress"], particle_fields(2, 8, expected)["stress"])


@pytest.mark.parametrize("time,side", [(7.0, "after the last"), (0.5006, "after the last"),
                                       (-1.0, "before the first")])
def test_load_particles_time_outside_the_run_is_an_error(make_run, time, side):
    """Not the first or last output in its place: that one describes another time."""
    run_dir = make_run(times=(0.0, 0.25, 0.5))
    with pytest.raises(TimeOutsideRunError,
                       match=rf"no output at time {time:g} s in .*: it is {side} output \(the "
                             r"outputs run from 0 to 0.5 s; output times \[s\]: 0 0.25 0.5\)"):
        load_particles(run_dir, time=time)
    with pytest.raises(TimeOutsideRunError, match="finite"):
        load_particles(run_dir, time=float("nan"))


def test_load_particles_from_file(make_run):
    run_dir = make_run(times=(0.0, 0.25))
    data = load_particles(run_dir / "particles_000000.h5")
    assert data["time"] == 0.0 and data["step"] == 0


def test_load_particles_time_with_file_is_an_error(make_run):
    run_dir = make_run(times=(0.0,))
    with pytest.raises(ValueError, match="run directory"):
        load_particles(run_dir / "particles_000000.h5", time=0.0)


def test_load_particles_fortran_style_attributes(make_run):
    run_dir = make_run(dim=3, times=(0.0, 1.5), fortran_style=True, name="slope")
    data = load_particles(run_dir)
    assert data["time"] == 1.5 and isinstance(data["time"], float)
    assert data["step"] == 10 and isinstance(data["step"], int)
    assert data["dimension"] == 3
    assert data["case_name"] == "slope"


def test_load_particles_only_position(tmp_path):
    position = np.arange(6.0).reshape(2, 3)
    write_output(tmp_path / "particles_000000.h5", 0.0, 0, 3, {"position": position})
    data = load_particles(tmp_path)
    arrays = {k for k, v in data.items() if isinstance(v, np.ndarray)}
    assert arrays == {"position"}
    np.testing.assert_array_equal(data["position"], position)


def test_load_particles_missing_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="run directory not found"):
        load_particles(tmp_path / "outputs" / "nothing")


def test_load_particles_no_output(tmp_path):
    with pytest.raises(FileNotFoundError, match="no particles_NNNNNN.h5 output"):
        load_particles(tmp_path)


def test_load_particles_missing_position(tmp_path):
    write_output(tmp_path / "particles_000000.h5", 0.0, 0, 2, {"mass": np.ones(4)})
    with pytest.raises(ValueError, match="/particles/position is missing"):
        load_particles(tmp_path)


def test_load_particles_missing_group(tmp_path):
    with h5py.File(tmp_path / "particles_000000.h5", "w") as h5file:
        h5file.attrs["time"] = 0.0
        h5file.attrs["step"] = 0
    with pytest.raises(ValueError, match="group /particles is missing"):
        load_particles(tmp_path)


def test_load_particles_transposed_position(tmp_path):
    # (3, n) is what a Fortran array of shape (n, 3) looks like when written unchanged.
    write_output(tmp_path / "particles_000000.h5", 0.0, 0, 3, {"position": np.zeros((3, 5))})
    with pytest.raises(ValueError, match=r"shape \(3, 5\), expected \(n, 3\)"):
        load_particles(tmp_path)


def test_load_particles_inconsistent_rows(tmp_path):
    write_output(tmp_path / "particles_000000.h5", 0.0, 0, 2,
                 {"position": np.zeros((4, 3)), "mass": np.ones(3)})
    with pytest.raises(ValueError, match="mass has shape .*expected 4 rows"):
        load_particles(tmp_path)


# ----------------------------------------------------------------------------- load_grid
def test_load_grid(make_run):
    grid = {"position": np.arange(12.0).reshape(4, 3), "mass": np.array([1.0, 2.0, 3.0, 4.0]),
            "velocity": np.zeros((4, 3))}
    run_dir = make_run(times=(0.0, 0.5), grid=grid)
    data = load_grid(run_dir, time=0.4)
    assert data["time"] == 0.5
    np.testing.assert_array_equal(data["position"], grid["position"])
    np.testing.assert_array_equal(data["mass"], grid["mass"])


def test_load_grid_absent(make_run):
    assert load_grid(make_run(times=(0.0,))) is None


# ----------------------------------------------------------------------------- load_history
def test_load_history_columns(make_run):
    history = load_history(make_run())
    assert list(history) == ["time", "step", "kinetic_energy", "strain_energy",
                             "potential_energy", "damping_work", "total"]
    np.testing.assert_allclose(history["time"], [0.0, 0.1, 0.2, 0.3, 0.4])
    np.testing.assert_array_equal(history["step"], [0, 10, 20, 30, 40])
    np.testing.assert_array_equal(history["kinetic_energy"], [10.0, 8.0, 6.0, 4.0, 2.0])


def test_load_history_from_file_path(make_run):
    history = load_history(make_run() / "history.csv")
    assert history["total"].shape == (5,)


def test_load_history_single_row(tmp_path):
    write_history(tmp_path / "history.csv", [(0.0, 0, 1.0, 2.0, 3.0, 0.0, 6.0)])
    history = load_history(tmp_path)
    assert history["total"].shape == (1,)
    assert history["total"][0] == 6.0


def test_load_history_header_only(tmp_path):
    write_history(tmp_path / "history.csv", [])
    history = load_history(tmp_path)
    assert history["time"].shape == (0,)
    assert "total" in history


def test_load_history_missing(tmp_path):
    with pytest.raises(FileNotFoundError, match="history file not found: .*history.csv"):
        load_history(tmp_path)


def test_load_history_missing_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="no_run"):
        load_history(tmp_path / "no_run")


def test_load_history_ragged_row(tmp_path):
    path = tmp_path / "history.csv"
    path.write_text("time,step,total\n0.0,0,1.0\n0.1,1\n")
    with pytest.raises(ValueError, match="history.csv"):
        load_history(tmp_path)


def test_load_history_without_time_column(tmp_path):
    (tmp_path / "history.csv").write_text("step,total\n0,1.0\n")
    with pytest.raises(ValueError, match="no 'time' column"):
        load_history(tmp_path)
