"""mpm_post.profiles: deposit profiles on synthetic particle sets with known answers."""

import math

import numpy as np
import pytest
from mpm_post_fakerun import POSTPROC, write_output

from mpm_post.cli import main
from mpm_post.profiles import (bin_edges, failure_surface, free_surface, height_at_wall,
                               load_reference_profile, particle_half_size,
                               rms_height_difference, slip_angle, toe_position)

SPACING = 0.01          # particle spacing of the synthetic sets [m]
HALF = 0.5 * SPACING    # particle half-size [m]
# Sums of a few multiples of the spacing: exact to round-off (a few ulp of 0.1 m).
EXACT = 1e-12


def grid_block(width, height, spacing=SPACING, x0=0.0):
    """Particle centres filling [x0, x0 + width] x [0, height] on a regular grid."""
    xs = x0 + (np.arange(round(width / spacing)) + 0.5) * spacing
    ys = (np.arange(round(height / spacing)) + 0.5) * spacing
    x, y = np.meshgrid(xs, ys, indexing="ij")
    return x.ravel(), y.ravel()


def triangle(width, height, spacing=SPACING):
    """Columns of particles under the line h(x) = height (1 - x / width).

    Column i (centre x_i) holds floor(h(x_i) / spacing) particles, so its top is that count
    times the spacing: the known answer of free_surface with one bin per column.
    """
    xs, ys, tops = [], [], []
    for i in range(round(width / spacing)):
        xc = (i + 0.5) * spacing
        count = math.floor(height * (1.0 - xc / width) / spacing + 1e-9)
        xs += [xc] * count
        ys += [(j + 0.5) * spacing for j in range(count)]
        tops.append(count * spacing)
    return np.array(xs), np.array(ys), np.array(tops)


# --- particle_half_size, bin_edges ---------------------------------------------------------

def test_particle_half_size_2d_and_3d():
    assert particle_half_size(0.01**2, 2) == pytest.approx(0.005, rel=1e-14)
    assert particle_half_size(np.array([0.02**3]), 3)[0] == pytest.approx(0.01, rel=1e-14)
    with pytest.raises(ValueError, match="dimension"):
        particle_half_size(1.0, 1)
    with pytest.raises(ValueError, match=">= 0"):
        particle_half_size(-1.0, 2)


def test_bin_edges_cover_the_range_exactly():
    edges = bin_edges(0.0, 0.5, 0.0025)
    assert edges[0] == 0.0 and edges[-1] == 0.5
    assert edges.size == 201
    assert np.allclose(np.diff(edges), 0.0025, rtol=1e-12)
    # a width that does not divide the range: the bins shrink to fit
    edges = bin_edges(0.0, 1.0, 0.3)
    assert edges.size == 5 and np.all(np.diff(edges) <= 0.3)
    with pytest.raises(ValueError):
        bin_edges(0.0, 1.0, 0.0)
    with pytest.raises(ValueError):
        bin_edges(1.0, 1.0, 0.1)


# --- free_surface --------------------------------------------------------------------------

def test_free_surface_of_a_rectangular_block():
    x, y = grid_block(0.2, 0.1)
    centres, height = free_surface(x, y, HALF, bin_edges(0.0, 0.3, SPACING))
    assert centres.size == 30
    assert np.allclose(centres, (np.arange(30) + 0.5) * SPACING, atol=EXACT)
    assert np.allclose(height[:20], 0.1, atol=EXACT)   # top of the block
    assert np.all(height[20:] == 0.0)                   # empty bins beyond it


def test_free_surface_with_a_bin_count_spans_the_particles():
    x, y = grid_block(0.2, 0.1)
    centres, height = free_surface(x, y, HALF, 10)
    assert centres[0] == pytest.approx(0.01, abs=EXACT)   # bins of 2 cm from 0 to 0.2
    assert centres[-1] == pytest.approx(0.19, abs=EXACT)
    assert np.allclose(height, 0.1, atol=EXACT)


def test_free_surface_of_a_triangle_deposit():
    x, y, tops = triangle(0.3, 0.1)
    centres, height = free_surface(x, y, HALF, bin_edges(0.0, 0.3, SPACING))
    assert np.allclose(height, tops, atol=EXACT)
    # and the staircase stays within one spacing below the line it samples
    line = 0.1 * (1.0 - centres / 0.3)
    assert np.all(height <= line + EXACT) and np.all(height > line - SPACING)


def test_free_surface_empty_bin_inside_the_deposit_is_zero():
    x, y = grid_block(0.2, 0.1)
    keep = (x < 0.08) | (x > 0.1)      # remove two columns of particles
    _, height = free_surface(x[keep], y[keep], HALF, bin_edges(0.0, 0.2, SPACING))
    assert np.all(height[8:10] == 0.0)
    assert np.allclose(height[:8], 0.1, atol=EXACT) and np.allclose(height[10:], 0.1, atol=EXACT)


def test_free_surface_per_particle_half_sizes_and_outside_particles():
    x = np.array([0.05, 0.05, 0.15, 0.5])      # the last one lies outside the bins
    y = np.array([0.01, 0.03, 0.02, 0.9])
    half = np.array([0.01, 0.002, 0.004, 0.1])
    _, height = free_surface(x, y, half, np.array([0.0, 0.1, 0.2]))
    assert height == pytest.approx([0.032, 0.024], abs=EXACT)
    with pytest.raises(ValueError, match="half_size"):
        free_surface(x, y, half[:2], 2)
    with pytest.raises(ValueError, match="edges"):
        free_surface(x, y, half, np.array([0.2, 0.1]))


# --- toe_position --------------------------------------------------------------------------

def test_toe_of_a_block_is_its_right_face():
    x, y = grid_block(0.2, 0.1)
    assert toe_position(x, y, HALF) == pytest.approx(0.2, abs=EXACT)


def test_toe_ignores_a_stray_particle_beyond_the_front():
    x, y = grid_block(0.2, 0.1)
    x = np.append(x, 0.35)      # 0.145 m of empty floor between it and the front
    y = np.append(y, 0.005)
    assert toe_position(x, y, HALF) == pytest.approx(0.2, abs=EXACT)
    # a gap of less than one particle size is still part of the deposit
    x[-1] = 0.2 + 0.5 * SPACING + HALF
    assert toe_position(x, y, HALF) == pytest.approx(x[-1] + HALF, abs=EXACT)
    # and a larger allowed gap takes the stray one in
    x[-1] = 0.35
    assert toe_position(x, y, HALF, max_gap=0.2) == pytest.approx(0.355, abs=EXACT)


def test_toe_of_a_triangle_and_of_a_thin_tail():
    x, y, tops = triangle(0.3, 0.1)
    last_column = np.nonzero(tops > 0)[0].max()
    assert toe_position(x, y, HALF) == pytest.approx((last_column + 1) * SPACING, abs=EXACT)
    # a one-particle-thick tail from 0.2 to 0.3 m beside a block
    bx, by = grid_block(0.2, 0.1)
    tx, ty = grid_block(0.1, SPACING, x0=0.2)
    x, y = np.concatenate([bx, tx]), np.concatenate([by, ty])
    assert toe_position(x, y, HALF) == pytest.approx(0.3, abs=EXACT)
    # a deposit thicker than 1.5 spacings ends at the block
    assert toe_position(x, y, HALF, min_height=1.5 * SPACING) == pytest.approx(0.2, abs=EXACT)


def test_toe_with_no_deposit_is_nan():
    assert math.isnan(toe_position([0.1], [0.0], 0.001, min_height=0.01))
    assert math.isnan(toe_position([], [], 0.001))
    with pytest.raises(ValueError, match="differ"):
        toe_position([0.1, 0.2], [0.0], HALF)


# --- height_at_wall ------------------------------------------------------------------------

def test_height_at_wall_of_block_and_triangle():
    x, y = grid_block(0.2, 0.1)
    assert height_at_wall(x, y, HALF) == pytest.approx(0.1, abs=EXACT)
    x, y, tops = triangle(0.3, 0.1)
    assert height_at_wall(x, y, HALF) == pytest.approx(tops[0], abs=EXACT)
    # a wall on the right of the block
    bx, by = grid_block(0.2, 0.05)
    assert height_at_wall(bx, by, HALF, x_wall=0.2) == pytest.approx(0.05, abs=EXACT)


def test_height_at_wall_without_particles_near_it_is_zero():
    x, y = grid_block(0.1, 0.1, x0=0.1)
    assert height_at_wall(x, y, HALF) == 0.0
    assert height_at_wall(x, y, HALF, width=0.11) == pytest.approx(0.1, abs=EXACT)


# --- rms_height_difference -----------------------------------------------------------------

def test_rms_of_identical_and_shifted_profiles():
    xs = np.linspace(0.0, 0.4, 41)
    hs = 0.1 * (1.0 - xs / 0.4)
    assert rms_height_difference(xs, hs, xs, hs) == (0.0, 0.0)
    rms, max_abs = rms_height_difference(xs, hs + 0.002, xs, hs)
    assert rms == pytest.approx(0.002, rel=1e-12) and max_abs == pytest.approx(0.002, rel=1e-12)


def test_rms_interpolates_and_skips_reference_points_outside():
    xs = np.array([0.0, 0.1, 0.2])
    hs = np.array([0.1, 0.05, 0.0])                   # a straight line
    x_ref = np.array([0.05, 0.15, 0.3, -0.1])         # the last two lie outside
    h_ref = np.array([0.075, 0.025 + 0.003, 5.0, 5.0])
    rms, max_abs = rms_height_difference(xs, hs, x_ref, h_ref)
    assert max_abs == pytest.approx(0.003, rel=1e-12)
    assert rms == pytest.approx(0.003 / math.sqrt(2.0), rel=1e-12)


def test_rms_of_a_block_surface_against_a_reference_triangle():
    x, y = grid_block(0.2, 0.1)
    centres, height = free_surface(x, y, HALF, bin_edges(0.0, 0.4, SPACING))
    x_ref = np.array([0.05, 0.15, 0.25, 0.35])
    h_ref = np.array([0.1, 0.1, 0.0, 0.0])   # the block: matches at points away from its edge
    assert rms_height_difference(centres, height, x_ref, h_ref) == (0.0, 0.0)
    h_ref = np.array([0.09, 0.1, 0.02, 0.0])
    rms, max_abs = rms_height_difference(centres, height, x_ref, h_ref)
    assert max_abs == pytest.approx(0.02, abs=EXACT)
    assert rms == pytest.approx(math.sqrt((0.01**2 + 0.02**2) / 4.0), rel=1e-9)


def test_rms_errors_and_nan_points():
    with pytest.raises(ValueError, match="do not overlap"):
        rms_height_difference([0.0, 0.1], [1.0, 1.0], [0.5], [1.0])
    with pytest.raises(ValueError, match="increasing"):
        rms_height_difference([0.1, 0.0], [1.0, 1.0], [0.05], [1.0])
    rms, _ = rms_height_difference([0.0, 0.1, 0.2], [1.0, np.nan, 1.0], [0.1, 0.15],
                                   [1.0, np.nan])
    assert rms == 0.0


# --- failure_surface, slip_angle -----------------------------------------------------------

def sliding_wedge():
    """A block whose particles above the line y = 0.1 - 0.5 x moved 5 cm, those below none."""
    x, y = grid_block(0.2, 0.1)
    line = 0.1 - 0.5 * x
    moved = np.where(y < line, 0.0, 0.05)
    return x, y, moved


def test_failure_surface_follows_the_boundary_between_static_and_moved():
    x, y, moved = sliding_wedge()
    centres, top = failure_surface(x, y, moved, 1e-3, bin_edges(0.0, 0.2, SPACING),
                                   half_size=HALF)
    line = 0.1 - 0.5 * centres
    # the last column has the line below its lowest particle centre: nothing static there
    assert np.isnan(top[-1]) and line[-1] < HALF
    # elsewhere the top edge of the highest static particle of each column lies within one
    # spacing below the line through the column centre (+ the half-size added)
    top, line = top[:-1], line[:-1]
    assert np.all(top <= line + HALF + EXACT) and np.all(top > line - SPACING)
    # without half_size: the centres of those particles, half a spacing lower
    _, centre_top = failure_surface(x, y, moved, 1e-3, bin_edges(0.0, 0.2, SPACING))
    assert np.allclose(top - centre_top[:-1], HALF, atol=EXACT)


def test_slip_angle_of_the_wedge_and_of_exact_lines():
    x, y, moved = sliding_wedge()
    centres, top = failure_surface(x, y, moved, 1e-3, bin_edges(0.0, 0.2, SPACING), HALF)
    # a staircase sampling of a 26.57 deg line: its fit is within a degree of it
    assert slip_angle(centres, top) == pytest.approx(math.degrees(math.atan(0.5)), abs=1.0)
    xs = np.linspace(0.0, 0.2, 11)
    assert slip_angle(xs, 0.1 - 0.5 * xs) == pytest.approx(math.degrees(math.atan(0.5)),
                                                           rel=1e-12)
    assert slip_angle(xs, 0.5 * xs) == pytest.approx(-math.degrees(math.atan(0.5)), rel=1e-12)


def test_slip_angle_y_range_drops_the_flat_parts():
    xs = np.linspace(0.0, 0.3, 31)
    ys = np.clip(0.12 - xs, 0.0, 0.1)        # flat top, a 45 deg slope, then the floor
    assert slip_angle(xs, ys) < 40.0
    assert slip_angle(xs, ys, y_range=(0.0, 0.1)) == pytest.approx(45.0, rel=1e-9)


def test_failure_surface_empty_bins_and_edge_cases():
    x, y, moved = sliding_wedge()
    centres, top = failure_surface(x, y, moved, 1e-3, bin_edges(0.0, 0.4, SPACING))
    assert np.all(np.isnan(top[centres > 0.2]))        # no static particle beyond the block
    assert np.all(np.isfinite(top[centres < 0.19]))
    # everything moved: no surface at all
    _, top = failure_surface(x, y, np.ones_like(x), 1e-3, 5)
    assert np.all(np.isnan(top))
    assert math.isnan(slip_angle(centres, np.full_like(centres, np.nan)))
    assert math.isnan(slip_angle([0.1, 0.1], [0.0, 1.0]))     # vertical: no dip
    assert math.isnan(slip_angle([0.1], [0.0]))
    with pytest.raises(ValueError, match="threshold"):
        failure_surface(x, y, moved, 0.0, 5)
    with pytest.raises(ValueError, match="displacement_norm"):
        failure_surface(x, y, moved[:3], 1e-3, 5)


# --- load_reference_profile ----------------------------------------------------------------

def test_load_reference_profile_tabs_blanks_and_comments(tmp_path):
    path = tmp_path / "surface.txt"
    path.write_text("# x z\n0.0\t0.1\n0.1   0.05\n  0.2 0.0\n")
    x, h = load_reference_profile(path)
    assert x.tolist() == [0.0, 0.1, 0.2] and h.tolist() == [0.1, 0.05, 0.0]


def test_load_reference_profile_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.txt"):
        load_reference_profile(tmp_path / "missing.txt")
    bad = tmp_path / "three.txt"
    bad.write_text("0 1 2\n3 4 5\n")
    with pytest.raises(ValueError, match="three.txt"):
        load_reference_profile(bad)
    text = tmp_path / "text.txt"
    text.write_text("0 a\n")
    with pytest.raises(ValueError, match="text.txt"):
        load_reference_profile(text)


def test_load_the_bui2008_data():
    data = POSTPROC.parent / "validation" / "bui2008" / "data"
    if not data.is_dir():
        pytest.skip("validation/bui2008/data not present")
    x, h = load_reference_profile(data / "Data_Buietal_2008_experimental_surface.txt")
    assert x.size == 23 and x[-1] == pytest.approx(0.442348498)
    assert h[np.argmin(x)] == pytest.approx(0.099231753)
    xf, hf = load_reference_profile(data / "Data_Buietal_2008_experimental_failure_surface.txt")
    assert xf.size == 9
    assert slip_angle(xf, hf) == pytest.approx(33.0, abs=0.5)    # as the README says


# --- python -m mpm_post profile ------------------------------------------------------------

def block_run(tmp_path, stray=False):
    x, y = grid_block(0.2, 0.1)
    if stray:
        x, y = np.append(x, 0.35), np.append(y, 0.005)
    n = x.size
    position = np.zeros((n, 3))
    position[:, 0], position[:, 1] = x, y
    run_dir = tmp_path / "block"
    run_dir.mkdir()
    write_output(run_dir / "particles_000000.h5", 0.0, 0, 2,
                 {"position": position, "volume": np.full(n, SPACING**2),
                  "mass": np.full(n, 1.0)})
    return run_dir


def test_cli_profile_with_reference(tmp_path, capsys):
    run_dir = block_run(tmp_path, stray=True)
    reference = tmp_path / "ref.txt"
    reference.write_text("0.05 0.1\n0.15 0.1\n0.25 0.0\n")
    code = main(["profile", str(run_dir), "--reference", str(reference)])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "toe [m]: 0.2\n" in out
    assert "height at wall [m]: 0.1\n" in out
    assert "reference toe [m]: 0.25" in out
    assert "RMS height difference [m]: 0\n" in out


def test_cli_profile_without_reference_and_errors(tmp_path, capsys):
    run_dir = block_run(tmp_path)
    code = main(["profile", str(run_dir), "--min-height", "0.2"])
    out, _ = capsys.readouterr()
    assert code == 0 and "toe [m]: nan" in out and "RMS" not in out
    code = main(["profile", str(run_dir), "--reference", str(tmp_path / "none.txt")])
    _, err = capsys.readouterr()
    assert code == 1 and "reference profile not found" in err
