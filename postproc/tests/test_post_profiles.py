"""mpm_post.profiles: deposit profiles on synthetic particle sets with known answers."""

import math

import h5py
import numpy as np
import pytest
from mpm_post_fakerun import POSTPROC, write_output

from mpm_post.cli import main
from mpm_post.io import load_terrain
from mpm_post.profiles import (bin_edges, failure_surface, free_surface, height_at_wall,
                               load_reference_profile, particle_half_size, particle_size,
                               rms_height_difference, slip_angle, surface_profile,
                               terrain_height, toe_position)

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


def trapezoid(spacing=SPACING, top=0.1, flat=0.1, foot=0.3):
    """Particles on a regular grid of ``spacing`` whose centres lie under a trapezoid.

    The line: ``top`` [m] from x = 0 to ``flat``, then straight down to 0 at ``foot``.
    Returns x, y and the line as a function of x.
    """
    def line(x):
        return np.where(x <= flat, top, top * np.clip((foot - x) / (foot - flat), 0.0, 1.0))

    x, y = grid_block(foot, top, spacing)
    keep = y < line(x)
    return x[keep], y[keep], line


@pytest.mark.parametrize("width", [0.25, 0.5, 0.7, 1.0, 1.3, 2.5])
@pytest.mark.parametrize("offset", [0.0, 0.37])
def test_free_surface_of_a_trapezoid_for_any_bin_width(width, offset):
    """Within half a spacing of the line at the columns each bin reaches, for any bins.

    The top particle of a column lies less than one spacing below the line at the column's
    centre and its top is half a spacing above its centre: the column's top is within s/2 of
    the line there. A bin takes the tops of the columns whose domains overlap it, the columns
    whose centres lie within the bin widened by s/2 on each side, so its height lies within
    s/2 of the line's values at those centres. A bin left empty, or given a lower particle
    (the dips of a binning by centres when bins are narrower than the spacing), falls below.
    """
    x, y, line = trapezoid()
    columns = np.unique(x)
    edges = bin_edges(-offset * SPACING, 0.3, width * SPACING)
    _, height = free_surface(x, y, HALF, edges)
    checked = 0
    for low, high, value in zip(edges[:-1], edges[1:], height):
        # reached by more than round-off (free_surface's EDGE_ROUNDOFF)
        reached = columns[(columns > low - HALF + EXACT) & (columns < high + HALF - EXACT)]
        if reached.size == 0:
            assert value == 0.0
            continue
        assert line(reached).min() - HALF - EXACT <= value <= line(reached).max() + HALF + EXACT
        checked += 1
    assert checked >= 0.9 * height.size       # all but the bins beyond the deposit's ends
    flat = (edges[1:] + HALF <= 0.1) & (edges[:-1] >= 0.0)
    assert np.allclose(height[flat], 0.1, atol=EXACT)    # the flat top exactly, every bin


def stretched_deposit(spacing=SPACING, stretch=1.5, rows=8, columns=30):
    """A layer stretched along x as a spreading deposit: particles of area spacing**2 on rows
    stretch * spacing apart along x and spacing / stretch apart in height, every other row
    shifted by half a column. The top row leaves gaps of (stretch - 1) spacing between its
    particle domains, which the row below covers."""
    dx, dy = stretch * spacing, spacing / stretch
    x = np.concatenate([(np.arange(columns) + 0.5 + 0.5 * (j % 2)) * dx for j in range(rows)])
    y = np.concatenate([np.full(columns, (j + 0.5) * dy) for j in range(rows)])
    return x, y, rows * dy


def test_surface_profile_of_a_stretched_deposit_has_no_dips():
    x, y, top = stretched_deposit()
    half = particle_half_size(np.full(x.size, SPACING**2), 2)      # SPACING / 2 each
    row = SPACING / 1.5
    top_row, below = top - 0.5 * row + HALF, top - 1.5 * row + HALF
    for width in (0.3 * SPACING, None, 1.7 * SPACING):
        centres, height, used = surface_profile(x, y, half, 0.0, 0.45, width)
        assert used >= particle_size(half) - EXACT
        # inside, every bin meets a domain of the top row (gaps of half a spacing between
        # them); at the two ends of the layer the row below, one row lower: no dip deeper
        inside = (centres > 1.5 * SPACING + used) & (centres < 0.45 - 1.5 * SPACING - used)
        assert np.count_nonzero(inside) > 10
        assert np.allclose(height[inside], top_row, atol=EXACT)
        assert np.all((height >= below - EXACT) & (height <= top_row + EXACT))
    # a binning by centres on bins of the particle size leaves bins with no top particle:
    # the sawtooth of the issue
    edges = bin_edges(0.0, 0.45, SPACING)
    by_centre = np.zeros(edges.size - 1)
    np.maximum.at(by_centre, np.searchsorted(edges, x, side="right") - 1, y + HALF)
    assert np.min(by_centre[2:-2]) <= below + EXACT


def test_surface_profile_widens_narrow_bins_and_checks_its_range():
    x, y = grid_block(0.2, 0.1)
    centres, height, width = surface_profile(x, y, HALF, 0.0, 0.2, 0.001)
    assert width == pytest.approx(SPACING, abs=EXACT) and centres.size == 20
    assert np.allclose(height, 0.1, atol=EXACT)
    _, _, width = surface_profile(x, y, HALF, 0.0, 0.2, 0.03)
    assert width >= 0.03           # 6 bins of 0.0333 m, never narrower than asked
    with pytest.raises(ValueError, match="empty range"):
        surface_profile(x, y, HALF, 0.2, 0.2)


# --- terrain_height ------------------------------------------------------------------------

def plane_terrain(z0=0.2, slope=0.1, size=4.0, n=4):
    """Triangles of the plane z = z0 + slope x over [0, size]^2, n x n squares of 2 each."""
    edge = np.linspace(0.0, size, n + 1)
    corners = []
    for i in range(n):
        for j in range(n):
            a, b = (edge[i], edge[j]), (edge[i + 1], edge[j])
            c, d = (edge[i + 1], edge[j + 1]), (edge[i], edge[j + 1])
            for tri in ((a, b, c), (a, c, d)):
                corners.append([(px, py, z0 + slope * px) for px, py in tri])
    return np.array(corners)


def test_terrain_height_of_a_plane_and_outside_it():
    corners = plane_terrain()
    x = np.array([0.0, 1.3, 2.0, 3.99, 4.5])
    y = np.array([0.0, 2.7, 2.0, 0.5, 1.0])
    z = terrain_height(x, y, corners)
    assert z[:4] == pytest.approx(0.2 + 0.1 * x[:4], abs=EXACT)   # corners and edges count
    assert np.isnan(z[4])


def test_terrain_height_takes_the_floor_below_an_overhang():
    ground = plane_terrain(z0=0.0, slope=0.0)
    roof = plane_terrain(z0=1.0, slope=0.0)
    corners = np.concatenate([ground, roof])
    x, y = np.array([1.0, 1.0]), np.array([1.0, 1.0])
    assert terrain_height(x, y, corners, below=np.array([0.5, 1.5])) == \
        pytest.approx([0.0, 1.0], abs=EXACT)
    assert terrain_height(x, y, corners, below=np.array([-0.5, -0.5])) == \
        pytest.approx([0.0, 0.0], abs=EXACT)     # under everything: the lowest crossing
    with pytest.raises(ValueError, match="shape"):
        terrain_height(x, y, corners[:, :2])


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


# --- profile of 3D runs: heights above the floor or the terrain ----------------------------

def layer_3d(x0, x1, thickness, base, spacing=SPACING, y0=1.0, rows=2):
    """Particle centres of a layer over [x0, x1] x [y0, y0 + rows spacing], ``thickness`` [m]
    thick, its bottom at ``base(x)`` [m] under each column."""
    xs = x0 + (np.arange(round((x1 - x0) / spacing)) + 0.5) * spacing
    ys = y0 + (np.arange(rows) + 0.5) * spacing
    zs = (np.arange(round(thickness / spacing)) + 0.5) * spacing
    x, y, z = np.meshgrid(xs, ys, zs, indexing="ij")
    x, y, z = x.ravel(), y.ravel(), z.ravel()
    return np.column_stack([x, y, z + base(x)])


def write_3d_run(run_dir, layers, terrain=None):
    """A 3D run: one output per (time, positions); ``terrain``: (n, 3, 3) corners for a
    terrain.h5 in mpm_geo's layout (/terrain/position, the corners, /terrain/triangles)."""
    run_dir.mkdir()
    for index, (time, position) in enumerate(layers):
        write_output(run_dir / f"particles_{index:06d}.h5", time, index, 3,
                     {"position": position, "volume": np.full(position.shape[0], SPACING**3)})
    if terrain is not None:
        with h5py.File(run_dir / "terrain.h5", "w") as h5file:
            group = h5file.create_group("terrain")
            group.create_dataset("position", data=terrain.reshape(-1, 3))
            group.create_dataset("triangles", data=np.arange(terrain.shape[0] * 3,
                                                             dtype=np.int32))
    return run_dir


def test_cli_profile_3d_on_a_raised_floor(tmp_path, capsys):
    """A block 0.1 m high on a floor at z = 0.5 m spreads into a layer 0.05 m high."""
    def floor(x):
        return np.full(x.shape, 0.5)

    run_dir = write_3d_run(tmp_path / "raised", [(0.0, layer_3d(0.0, 0.2, 0.1, floor)),
                                                 (1.0, layer_3d(0.0, 0.3, 0.05, floor))])
    code = main(["profile", str(run_dir)])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "heights above: z = 0.5 m, the lowest particle bottom at t = 0 s" in out
    assert "toe [m]: 0.3\n" in out
    assert "height at wall [m]: 0.05\n" in out
    assert "max height [m]: 0.05\n" in out
    assert "runout from t = 0 s [m]: 0.1 (toe then 0.2)\n" in out
    code = main(["profile", str(run_dir), "--floor", "0"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "heights above: z = 0 m (--floor)" in out and "max height [m]: 0.55\n" in out


def test_cli_profile_3d_above_the_terrain(tmp_path, capsys):
    """A layer 0.04 m thick on the slope z = 0.2 + 0.1 x, away from x = 0, slides on and thins
    to 0.03 m: heights above the terrain, no height at a wall it never touched."""
    corners = plane_terrain(z0=0.2, slope=0.1)

    def ground(x):
        return 0.2 + 0.1 * x

    beyond = np.array([[4.5, 1.0, 0.7]])      # thrown past the terrain's edge (x = 4 m)
    run_dir = write_3d_run(tmp_path / "slide", [
        (0.0, layer_3d(1.0, 1.5, 0.04, ground)),
        (1.0, np.concatenate([layer_3d(2.0, 2.6, 0.03, ground), beyond]))], terrain=corners)
    code = main(["profile", str(run_dir)])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "left out: 1 particles beyond the terrain (no floor under them)\n" in out
    assert "heights above: the terrain (terrain.h5), straight below each particle" in out
    assert "toe [m]: 2.6\n" in out
    assert ("height at wall: does not apply (no particle within 0.01 m of the wall x = 0 m "
            "at t = 0 s; --wall X names another)") in out
    assert "max height [m]: 0.03\n" in out
    assert "runout from t = 0 s [m]: 1.1 (toe then 1.5)\n" in out
    # the surface of the figure: 0.03 m over the layer, 0 on the bare slope before it
    out_file = tmp_path / "slide.png"
    code = main(["plot", "profile", str(run_dir), "--out", str(out_file)])
    assert code == 0 and out_file.is_file()


def test_load_terrain(tmp_path):
    corners = plane_terrain()
    run_dir = write_3d_run(tmp_path / "run", [(0.0, layer_3d(1.0, 1.1, 0.02, np.zeros_like))],
                           terrain=corners)
    assert np.array_equal(load_terrain(run_dir), corners)
    assert np.array_equal(load_terrain(run_dir / "particles_000000.h5"), corners)
    assert load_terrain(tmp_path) is None
    with h5py.File(run_dir / "terrain.h5", "w") as h5file:
        h5file.create_dataset("terrain/position", data=np.zeros((4, 3)))
        h5file.create_dataset("terrain/triangles", data=np.arange(4))
    with pytest.raises(ValueError, match="do not describe triangles"):
        load_terrain(run_dir)
    code = main(["profile", str(run_dir)])
    assert code == 1
