"""Deposit profiles of granular collapses, from particle data (numpy arrays).

The functions take particle coordinates along the flow (``x`` [m]) and the vertical (``y``
[m], the floor at y = 0) and the half-size of each particle's domain (``half_size`` [m], a
number or one value per particle). In 2D the half-size of a particle of area V is sqrt(V) / 2;
see ``particle_half_size``. In 3D pass the horizontal distance of interest as ``x`` and the
vertical coordinate (z) as ``y``.

Used by validation/bui2008/check.py (Bui et al. 2008 column collapse) and by the ``profile``
command of ``python -m mpm_post``.
"""

from pathlib import Path

import numpy as np


def _as_float(name, values):
    array = np.asarray(values, dtype=float)
    if array.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array, got shape {array.shape}")
    return array


def _per_particle(name, values, n):
    """A number or an array of n numbers, as an array of n numbers."""
    array = np.asarray(values, dtype=float)
    if array.ndim == 0:
        return np.full(n, float(array))
    if array.shape != (n,):
        raise ValueError(f"{name} must be a number or an array of {n} values, "
                         f"got shape {array.shape}")
    return array


def _points(x, y, half_size=0.0):
    x = _as_float("x", x)
    y = _as_float("y", y)
    if x.shape != y.shape:
        raise ValueError(f"x and y differ in length: {x.size} and {y.size}")
    h = _per_particle("half_size", half_size, x.size)
    if np.any(h < 0.0):
        raise ValueError("half_size must be >= 0")
    return x, y, h


def particle_half_size(volume, dimension):
    """Half-size [m] of square (cubic) particle domains of the given areas (volumes).

    ``volume``: particle area [m2] in 2D, volume [m3] in 3D; ``dimension``: 2 or 3.
    Returns V**(1/dimension) / 2: for particles from a regular fill, dx / (2 ppc).
    """
    if dimension not in (2, 3):
        raise ValueError(f"dimension must be 2 or 3, got {dimension}")
    volume = np.asarray(volume, dtype=float)
    if np.any(volume < 0.0):
        raise ValueError("particle volumes must be >= 0")
    return 0.5 * volume ** (1.0 / dimension)


def bin_edges(start, stop, width):
    """Edges of equal bins of about ``width`` [m] covering [start, stop] [m] exactly."""
    if not width > 0.0:
        raise ValueError(f"bin width must be > 0, got {width}")
    if not stop > start:
        raise ValueError(f"empty range: [{start}, {stop}]")
    count = max(1, int(np.ceil((stop - start) / width - 1e-9)))
    return np.linspace(start, stop, count + 1)


def _edges(bins, low, high):
    """Bin edges from an edge array, or an integer count over [low, high]."""
    if np.ndim(bins) == 0:
        count = int(bins)
        if count != bins or count < 1:
            raise ValueError(f"bins must be a positive integer or an array of edges, got {bins}")
        if not high > low:
            high = low + 1.0
        return np.linspace(low, high, count + 1)
    edges = np.asarray(bins, dtype=float)
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise ValueError("bin edges must be an increasing 1-D array of at least 2 values")
    return edges


def _bin_index(x, edges):
    """Bin of each x (the last bin includes its right edge); -1 outside the edges."""
    index = np.searchsorted(edges, x, side="right") - 1
    index[x == edges[-1]] = edges.size - 2
    index[(x < edges[0]) | (x > edges[-1])] = -1
    return index


# Particle domains are narrowed by this fraction of their half-size before they are matched
# with the bins, so that a domain that ends on a bin edge (a regular fill, bins of the particle
# size) does not reach into the next bin by a round-off.
EDGE_ROUNDOFF = 1.0e-9


def _covered_bins(x, h, edges):
    """(particle, bin) pairs: each bin that the domain [x - h, x + h] of a particle overlaps.

    A domain reaching a bin by less than EDGE_ROUNDOFF of its half-size does not count; a
    particle of half-size 0 belongs to the bin of its centre (the last bin includes its right
    edge). Particles outside the edges give no pair.
    """
    nbins = edges.size - 1
    left, right = x - h * (1.0 - EDGE_ROUNDOFF), x + h * (1.0 - EDGE_ROUNDOFF)
    first = np.searchsorted(edges, left, side="right") - 1    # first bin with e[k+1] > left
    last = np.searchsorted(edges, right, side="left") - 1     # last bin with e[k] < right
    point = h == 0.0
    first[point] = last[point] = _bin_index(x[point], edges)
    inside = (right >= edges[0]) & (left <= edges[-1]) & (first <= last) & (last >= 0)
    inside &= first < nbins
    first = np.clip(first[inside], 0, nbins - 1)
    last = np.clip(last[inside], 0, nbins - 1)
    count = last - first + 1
    particle = np.repeat(np.flatnonzero(inside), count)
    offset = np.arange(particle.size) - np.repeat(np.cumsum(count) - count, count)
    return particle, np.repeat(first, count) + offset


def free_surface(x, y, half_size, bins):
    """Height of the deposit along x.

    ``x``, ``y``: particle positions [m] (the floor at y = 0); ``half_size``: particle
    half-size [m], a number or one per particle; ``bins``: bin edges along x [m] (an
    increasing array), or a number of equal bins from min(x - half_size) to
    max(x + half_size).

    Returns ``(x_centres, height)`` [m]: per bin the highest particle top, max(y + half_size),
    over the particles whose domain [x - half_size, x + half_size] overlaps the bin, and 0
    where no particle domain reaches the bin: a real gap of the deposit. Counting the whole
    domain rather than the centre makes the line independent of how the bins fall between the
    particle columns: a bin narrower than the particle spacing, or one that the top particles
    of a sheared deposit straddle, is not reported empty or as low as a lower particle (the
    sawtooth of a binning by centres). The price is a line up to one half-size wider than the
    particles' centres on each side of a step. Particles of half-size 0 count in the bin of
    their centre.
    """
    x, y, h = _points(x, y, half_size)
    low = float(np.min(x - h)) if x.size else 0.0
    high = float(np.max(x + h)) if x.size else 1.0
    edges = _edges(bins, low, high)
    centres = 0.5 * (edges[:-1] + edges[1:])
    height = np.zeros(centres.size)
    particle, index = _covered_bins(x, h, edges)
    np.maximum.at(height, index, (y + h)[particle])
    return centres, height


def particle_size(half_size):
    """The particle size [m] of a deposit: twice the median half-size.

    The median, so that a few particles whose volume grew by orders of magnitude (a thin fast
    front on a frictional floor, docs/input.md) do not set it.
    """
    h = np.asarray(half_size, dtype=float)
    if h.size == 0:
        raise ValueError("no particle")
    return 2.0 * float(np.median(h))


def surface_profile(x, y, half_size, start, stop, width=None):
    """The free surface from ``start`` to ``stop`` [m] on bins no narrower than the particles.

    ``width`` [m]: the bin width wanted (default: the particle size, particle_size); a width
    below the particle size is raised to it, and the bins are made equal and at least that
    wide over [start, stop]. With free_surface's rule (a bin takes the highest top of the
    particle domains that overlap it) a bin that wide always meets a particle where the gaps
    between neighbouring particle domains are narrower than one particle size, the gaps that
    toe_position also counts as inside the deposit. Wider gaps, real ones, read 0.

    Returns ``(x_centres, height, width)``: the bin centres and heights [m] of free_surface
    and the bin width used [m].
    """
    x, y, h = _points(x, y, half_size)
    size = particle_size(h)
    width = size if width is None else max(float(width), size)
    if not width > 0.0:
        raise ValueError(f"bin width must be > 0, got {width}")
    if not stop > start:
        raise ValueError(f"empty range: [{start}, {stop}]")
    count = max(1, int(np.floor((stop - start) / width + 1e-9)))
    edges = np.linspace(start, stop, count + 1)
    centres, height = free_surface(x, y, h, edges)
    return centres, height, float(edges[1] - edges[0])


def terrain_height(x, y, corners, below=None):
    """Height [m] of a terrain surface under points seen from above (z up).

    ``x``, ``y`` [m]: the points; ``corners``: (n, 3, 3) corners of the terrain's triangles
    [m] (triangle, corner, xyz), as io.load_terrain gives; ``below`` [m]: optional z of each
    point: of the surface crossings under a point, the highest at most at that z is taken (an
    overhang above the point is not its floor), the lowest crossing when all are above it.
    Returns one z per point, nan where no triangle lies under the point in plan view.
    """
    x, y = _as_float("x", x), _as_float("y", y)
    corners = np.asarray(corners, dtype=float)
    if corners.ndim != 3 or corners.shape[1:] != (3, 3):
        raise ValueError(f"corners must have shape (n, 3, 3), got {corners.shape}")
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    upright = np.abs(det) > 0.0           # vertical triangles have no height to give
    a, b, c, det = a[upright], b[upright], c[upright], det[upright]
    tol = 1.0e-12                          # barycentric round-off: a point on an edge counts
    result = np.full(x.size, np.nan)
    chunk = max(1, 2_000_000 // max(1, a.shape[0]))
    for start in range(0, x.size, chunk):
        px, py = x[start:start + chunk, None], y[start:start + chunk, None]
        u = ((b[:, 0] - px) * (c[:, 1] - py) - (c[:, 0] - px) * (b[:, 1] - py)) / det
        v = ((c[:, 0] - px) * (a[:, 1] - py) - (a[:, 0] - px) * (c[:, 1] - py)) / det
        w = 1.0 - u - v
        hit = (u >= -tol) & (v >= -tol) & (w >= -tol)
        z = u * a[:, 2] + v * b[:, 2] + w * c[:, 2]
        lowest = np.where(hit, z, np.inf).min(axis=1)
        if below is None:
            best = np.where(hit, z, -np.inf).max(axis=1)
        else:
            limit = _as_float("below", below)[start:start + chunk, None]
            best = np.where(hit & (z <= limit), z, -np.inf).max(axis=1)
            best = np.where(np.isfinite(best), best, lowest)
        best[~np.isfinite(lowest)] = np.nan
        result[start:start + chunk] = best
    return result


def toe_position(x, y, half_size, min_height=0.0, max_gap=None):
    """Front (toe) of the deposit that is contiguous from the wall [m].

    ``x``, ``y``, ``half_size`` as in ``free_surface``; ``min_height`` [m]: only particles whose
    top (y + half_size) is above it count as deposit; ``max_gap`` [m]: the largest gap allowed
    between neighbouring particle domains along x (default: one particle size, 2 half_size,
    the largest of the particles).

    The particles are swept from the smallest x (the wall) to the right; each one joins the
    deposit when its domain [x - half_size, x + half_size] starts within ``max_gap`` of the
    furthest point reached so far. The toe is that furthest point, max(x + half_size) of the
    joined particles. Why contiguity: a few particles thrown ahead of the front (numerical
    noise at the flow front, or a grain rolling away in an experiment) are not part of the
    deposit a measured profile describes; the largest x of all particles would follow them,
    the front of the contiguous mass does not. A gap of one particle size tolerates the
    spreading of the one-particle-thick tail of a deposit.

    Returns nan when no particle is above ``min_height``.
    """
    x, y, h = _points(x, y, half_size)
    keep = (y + h) > min_height
    if not np.any(keep):
        return float("nan")
    x, h = x[keep], h[keep]
    if max_gap is None:
        max_gap = 2.0 * float(np.max(h))
    if max_gap < 0.0:
        raise ValueError(f"max_gap must be >= 0, got {max_gap}")
    order = np.argsort(x - h, kind="stable")
    left = (x - h)[order]
    right = (x + h)[order]
    # particle k joins when left[k] <= max(right[:k]) + max_gap; the sweep stops at the
    # first particle that does not
    reach = np.maximum.accumulate(right)
    gaps = left[1:] - reach[:-1]
    breaks = np.nonzero(gaps > max_gap)[0]
    last = breaks[0] if breaks.size else left.size - 1
    return float(reach[last])


def height_at_wall(x, y, half_size, x_wall=0.0, width=None):
    """Height of the deposit at the wall [m].

    The highest particle top, max(y + half_size), among the particles whose centre lies within
    ``width`` [m] of the wall at ``x_wall`` [m] (default width: one particle size,
    2 half_size, the largest of the particles, so that the first column of particles counts).
    Returns 0 when no particle is that close to the wall.
    """
    x, y, h = _points(x, y, half_size)
    if width is None:
        width = 2.0 * float(np.max(h)) if h.size else 0.0
    near = np.abs(x - x_wall) <= width
    return float(np.max((y + h)[near])) if np.any(near) else 0.0


def max_height(x, y, half_size, x_max=None):
    """Largest height of the deposit [m].

    The highest particle top, max(y + half_size), among the particles whose centre lies at
    most at ``x_max`` [m] (default: all of them). Pass the toe (toe_position) as ``x_max`` to
    leave out particles thrown ahead of the deposit. Returns nan when no particle counts
    (for example when ``x_max`` is nan).
    """
    x, y, h = _points(x, y, half_size)
    keep = np.ones(x.size, dtype=bool) if x_max is None else x <= x_max
    return float(np.max((y + h)[keep])) if np.any(keep) else float("nan")


def rms_height_difference(x_sim, h_sim, x_ref, h_ref):
    """RMS and largest absolute difference between a simulated and a reference profile [m].

    The simulated profile (``x_sim`` increasing, ``h_sim``) is interpolated linearly at the
    reference abscissae ``x_ref`` that lie inside the range of both profiles; the differences
    h_sim - h_ref there give the root mean square and the largest magnitude. Points of either
    profile that are nan are dropped first. Returns ``(rms, max_abs)``; raises ValueError when
    the two profiles share no abscissa.
    """
    x_sim, h_sim = _as_float("x_sim", x_sim), _as_float("h_sim", h_sim)
    x_ref, h_ref = _as_float("x_ref", x_ref), _as_float("h_ref", h_ref)
    if x_sim.shape != h_sim.shape or x_ref.shape != h_ref.shape:
        raise ValueError("each profile needs as many heights as abscissae")
    valid = np.isfinite(x_sim) & np.isfinite(h_sim)
    x_sim, h_sim = x_sim[valid], h_sim[valid]
    valid = np.isfinite(x_ref) & np.isfinite(h_ref)
    x_ref, h_ref = x_ref[valid], h_ref[valid]
    if x_sim.size == 0 or x_ref.size == 0:
        raise ValueError("a profile has no finite point")
    if np.any(np.diff(x_sim) < 0.0):
        raise ValueError("x_sim must be increasing")
    common = (x_ref >= x_sim[0]) & (x_ref <= x_sim[-1])
    if not np.any(common):
        raise ValueError(f"the profiles do not overlap: simulated x in [{x_sim[0]:g}, "
                         f"{x_sim[-1]:g}], reference x in [{x_ref.min():g}, {x_ref.max():g}]")
    difference = np.interp(x_ref[common], x_sim, h_sim) - h_ref[common]
    return float(np.sqrt(np.mean(difference**2))), float(np.max(np.abs(difference)))


def failure_surface(x, y, displacement_norm, threshold, bins, half_size=0.0):
    """The failure (slip) surface: the top of the material that did not move.

    ``x``, ``y``: particle positions [m]; ``displacement_norm``: |u| of each particle since the
    start [m]; ``threshold`` [m]: particles with |u| < threshold are static, the others have
    moved; ``bins``: as in ``free_surface`` (the count form spans the static particles);
    ``half_size`` [m] (default 0): added to the static tops, to put the line on the upper edge
    of the static particles, between them and the moving ones, rather than on their centres.

    Returns ``(x_centres, y_slip)`` [m]: per bin the largest y (+ half_size) of the static
    particles; nan where a bin holds no static particle. Choose ``threshold`` well above the
    elastic settlement of the static part and well below the displacement of the slide.
    """
    x, y, h = _points(x, y, half_size)
    u = _per_particle("displacement_norm", displacement_norm, x.size)
    if not threshold > 0.0:
        raise ValueError(f"threshold must be > 0, got {threshold}")
    static = u < threshold
    xs, ys, hs = x[static], y[static], h[static]
    low = float(np.min(xs - hs)) if xs.size else 0.0
    high = float(np.max(xs + hs)) if xs.size else 1.0
    edges = _edges(bins, low, high)
    centres = 0.5 * (edges[:-1] + edges[1:])
    top = np.full(centres.size, -np.inf)
    index = _bin_index(xs, edges)
    inside = index >= 0
    np.maximum.at(top, index[inside], (ys + hs)[inside])
    top[np.isinf(top)] = np.nan
    return centres, top


def slip_angle(x, y, y_range=None):
    """Dip of the least-squares line through failure-surface points [degrees].

    ``x``, ``y`` [m]: points of the failure surface (nan points are dropped); ``y_range``
    [m]: optional (low, high), keep only points with low < y < high, to leave out the flat
    parts where the surface meets the column top or the floor. Returns the angle of the line
    below the horizontal, positive when it descends with x (a slip line away from the wall),
    and nan with fewer than two points or when they all share one x.
    """
    x, y = _as_float("x", x), _as_float("y", y)
    if x.shape != y.shape:
        raise ValueError(f"x and y differ in length: {x.size} and {y.size}")
    keep = np.isfinite(x) & np.isfinite(y)
    if y_range is not None:
        low, high = y_range
        keep &= (y > low) & (y < high)
    x, y = x[keep], y[keep]
    if x.size < 2 or np.ptp(x) == 0.0:
        return float("nan")
    slope = np.polyfit(x, y, 1)[0]
    return float(np.degrees(np.arctan(-slope)))


def load_reference_profile(path):
    """A reference profile from a text file of two columns, x [m] and height [m].

    Columns separated by tabs or blanks; lines starting with ``#`` are comments. Returns
    ``(x, height)`` as arrays in file order. Raises FileNotFoundError for a missing file and
    ValueError (naming the file) for any other shape or a non-numeric entry.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"reference profile not found: {path}")
    try:
        table = np.loadtxt(path, dtype=float, comments="#", ndmin=2)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    if table.shape[0] == 0 or table.shape[1] != 2:
        raise ValueError(f"{path}: expected two columns (x, height), got shape {table.shape}")
    return table[:, 0].copy(), table[:, 1].copy()
