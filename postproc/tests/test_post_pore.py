"""python -m mpm_post pore: pore pressure profiles and histories of a saturated column."""

import re

import h5py
import numpy as np
import pytest
from matplotlib.image import imread
from mpm_post_fakerun import particle_fields, write_output

from mpm_post.cli import main
from mpm_post.pore import load_pore_pressure, nearest_particles, profile_by_height

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# A column of 9 heights, two particles at each (x = 0.0125 and 0.0375), stored in a shuffled
# order so that the particle index is not the height order. Its extent at the first output is
# 0.05 .. 0.85 m: the default heights 1/4, 1/2, 3/4 of it are 0.25, 0.45, 0.65 m, exactly
# levels 2, 4 and 6.
LEVELS = 0.05 + 0.1 * np.arange(9)
ORDER = np.random.default_rng(7).permutation(18)
COLUMN_X = np.tile([0.0125, 0.0375], 9)[ORDER]
COLUMN_H = np.repeat(LEVELS, 2)[ORDER]
TIMES = (0.0, 0.5, 1.5)
SETTLEMENT = 0.01     # the heights shrink by 1 % per second


def pressure(x, h, t):
    """A known pore pressure [Pa]: zero at the top (h = 0.9 m), decaying with time; the two
    particles of one height differ by 1 kPa * x / 0.05 m."""
    return 1.0e4 * (0.9 - h) / 0.9 * np.exp(-t) + 2.0e4 * x * (1.0 + t)


def write_pore_run(run_dir, dim=2, times=TIMES, with_pore=True):
    """A saturated column: in 2D heights along y (z = 0), in 3D along z (y = 0.02 m)."""
    run_dir.mkdir()
    vertical = 1 if dim == 2 else 2
    for index, time in enumerate(times):
        fields = particle_fields(dim, COLUMN_H.size, time)
        position = np.zeros((COLUMN_H.size, 3))
        position[:, 0] = COLUMN_X
        if dim == 3:
            position[:, 1] = 0.02
        position[:, vertical] = COLUMN_H * (1.0 - SETTLEMENT * time)
        fields["position"] = position
        if with_pore:
            fields["pore_pressure"] = pressure(COLUMN_X, COLUMN_H, time)
            fields["eff_stress"] = fields["stress"].copy()
            fields["water_velocity"] = np.zeros((COLUMN_H.size, 3))
        write_output(run_dir / f"particles_{index:06d}.h5", time, 10 * index, dim, fields,
                     case_name="column", fortran_style=index == 1)
    return run_dir


def run(argv, capsys):
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def assert_png(path):
    """A PNG image with something drawn on it."""
    assert path.is_file() and path.read_bytes()[:8] == PNG_SIGNATURE
    image = imread(path)
    assert image.shape[0] > 100 and image.shape[1] > 100
    assert image[..., :3].std() > 0.01


LINE = re.compile(r"^(\w) = (\S+) m: particle (\d+) \(at \w = (\S+) m\), pore pressure (\S+) kPa "
                  r"at t = (\S+) s, (\S+) kPa at t = (\S+) s$")


def height_lines(out):
    """(axis, height, particle, its height, first kPa, first t, last kPa, last t) per line."""
    rows = []
    for line in out.splitlines():
        match = LINE.match(line)
        if match:
            axis, *values = match.groups()
            rows.append((axis, float(values[0]), int(values[1]), *map(float, values[2:])))
    return rows


def expected_particle(height):
    """The first particle in file order at the level nearest to ``height``."""
    level = LEVELS[np.argmin(np.abs(LEVELS - height))]
    return int(np.flatnonzero(COLUMN_H == level)[0])


@pytest.mark.parametrize("dim,axis", [(2, "y"), (3, "z")])
def test_pore_default_heights(tmp_path, capsys, dim, axis):
    run_dir = write_pore_run(tmp_path / "column", dim=dim)
    out_file = tmp_path / "figs" / "pore.png"
    code, out, err = run(["pore", str(run_dir), "--out", str(out_file)], capsys)
    assert code == 0, err
    assert_png(out_file)
    lines = out.splitlines()
    assert lines[0] == f"wrote {out_file}"
    assert lines[1] == (f"pore pressure of 18 particles at 3 outputs, t = 0 .. 1.5 s; heights "
                        f"along {axis}: 1/4, 1/2 and 3/4 of the particles' extent {axis} = "
                        "0.05 .. 0.85 m at t = 0 s")
    rows = height_lines(out)
    assert len(rows) == 3 and len(lines) == 5
    for (name, height, index, at, first, t0, last, t1), target in zip(rows, (0.25, 0.45, 0.65)):
        assert name == axis
        assert height == pytest.approx(target, rel=1e-6)
        assert index == expected_particle(target)
        assert at == pytest.approx(COLUMN_H[index], rel=1e-6)
        x, h = COLUMN_X[index], COLUMN_H[index]
        assert first == pytest.approx(pressure(x, h, 0.0) / 1e3, rel=1e-5)
        assert last == pytest.approx(pressure(x, h, 1.5) / 1e3, rel=1e-5)
        assert (t0, t1) == (0.0, 1.5)


def test_pore_given_heights(tmp_path, capsys):
    """--depths: the particle nearest at the first output, followed by index although the
    column settles; a height beyond the column takes its top particle."""
    run_dir = write_pore_run(tmp_path / "column")
    out_file = tmp_path / "pore.png"
    code, out, err = run(["pore", str(run_dir), "--out", str(out_file), "--depths", "0.12",
                          "0.82", "2"], capsys)
    assert code == 0, err
    assert_png(out_file)
    assert "heights along y: --depths\n" in out
    rows = height_lines(out)
    assert [row[1] for row in rows] == [0.12, 0.82, 2.0]
    assert [row[2] for row in rows] == [expected_particle(0.15), expected_particle(0.85),
                                        expected_particle(0.85)]
    for _, _, index, _, first, _, last, _ in rows:
        assert first == pytest.approx(pressure(COLUMN_X[index], COLUMN_H[index], 0.0) / 1e3,
                                      rel=1e-5)
        assert last == pytest.approx(pressure(COLUMN_X[index], COLUMN_H[index], 1.5) / 1e3,
                                     rel=1e-5)


def test_pore_two_column_positions(tmp_path, capsys):
    """Positions (n, 2) without a dimension attribute: the last coordinate is the vertical."""
    run_dir = tmp_path / "flat"
    run_dir.mkdir()
    for index, time in enumerate((0.0, 1.0)):
        with h5py.File(run_dir / f"particles_{index:06d}.h5", "w") as h5file:
            h5file.attrs["time"] = np.array([time])
            group = h5file.create_group("particles")
            group.create_dataset("position", data=np.stack([COLUMN_X, COLUMN_H], axis=1))
            group.create_dataset("pore_pressure", data=pressure(COLUMN_X, COLUMN_H, time))
    code, out, err = run(["pore", str(run_dir), "--out", str(tmp_path / "p.png"),
                          "--depths", "0.45"], capsys)
    assert code == 0, err
    (row,) = height_lines(out)
    assert row[0] == "y" and row[2] == expected_particle(0.45)
    history = load_pore_pressure(run_dir)
    assert history.case_name == "flat" and history.time.tolist() == [0.0, 1.0]
    np.testing.assert_array_equal(history.height, [COLUMN_H, COLUMN_H])


def test_pore_without_pore_pressure(make_run, tmp_path, capsys):
    run_dir = make_run(dim=2, name="dry")
    out_file = tmp_path / "pore.png"
    code, out, err = run(["pore", str(run_dir), "--out", str(out_file)], capsys)
    assert code == 2
    assert out == ""
    assert err == (f"mpm_post: error: {run_dir}/particles_000000.h5 has no pore_pressure: the "
                   "case has no pore_water (list pore_pressure in output.fields)\n")
    assert not out_file.exists()


def test_pore_missing_folder(tmp_path, capsys):
    code, out, err = run(["pore", str(tmp_path / "missing"), "--out",
                          str(tmp_path / "pore.png")], capsys)
    assert code == 2
    assert out == ""
    assert err == f"mpm_post: error: run directory not found: {tmp_path / 'missing'}\n"


def test_pore_vertical_axis(tmp_path, capsys):
    run_dir = write_pore_run(tmp_path / "column")
    code, _, err = run(["pore", str(run_dir), "--vertical-axis", "z", "--out",
                        str(tmp_path / "pore.png")], capsys)
    assert code == 2
    assert err.count("\n") == 1 and "the run is 2D" in err
    # y named explicitly is the default of a 2D run
    code, out, err = run(["pore", str(run_dir), "--vertical-axis", "y", "--out",
                          str(tmp_path / "pore.png")], capsys)
    assert code == 0, err
    assert "heights along y" in out


def test_pore_particle_count_changes(tmp_path, capsys):
    """Particles cannot be followed by index when an output holds other particles."""
    run_dir = write_pore_run(tmp_path / "column", times=(0.0, 0.5))
    with h5py.File(run_dir / "particles_000002.h5", "w") as h5file:
        h5file.attrs["time"] = 1.0
        group = h5file.create_group("particles")
        group.create_dataset("position", data=np.zeros((3, 3)))
        group.create_dataset("pore_pressure", data=np.zeros(3))
    code, _, err = run(["pore", str(run_dir), "--out", str(tmp_path / "pore.png")], capsys)
    assert code == 1
    assert "particles_000002.h5 holds 3 particles, the first output 18" in err


def test_profile_by_height_averages_one_height():
    height = np.array([0.3, 0.1, 0.3 + 1e-12, 0.2])
    values = np.array([1.0, 5.0, 3.0, 4.0])
    h, p = profile_by_height(height, values)
    np.testing.assert_allclose(h, [0.1, 0.2, 0.3], rtol=1e-9)
    np.testing.assert_allclose(p, [5.0, 4.0, 2.0])


def test_nearest_particles_first_in_file_order():
    assert nearest_particles([0.5, 0.25, 0.25, 1.0], [0.0, 0.25, 0.75, 0.9]) == [1, 1, 0, 3]
