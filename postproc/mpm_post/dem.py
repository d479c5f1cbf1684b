"""A digital elevation model (DEM) raster as an STL surface, for a layer's ``top`` or
``bottom`` (a body between a terrain and a slip surface) or ``contact.file``.

The raster is an ESRI ASCII grid (``.asc``), the plain format GIS tools export (GDAL: ``gdal_translate
-of AAIGrid``): a header of ``ncols``, ``nrows``, ``xllcorner`` or ``xllcenter``,
``yllcorner`` or ``yllcenter``, ``cellsize`` and optionally ``NODATA_value``, then ``nrows``
rows of ``ncols`` elevations, the northernmost row first. Each value is the elevation at its
cell's centre; the surface joins the centres by two triangles per square of four centres,
and leaves out a square with a NODATA corner (the layer then holds nothing there). The
surface is a height field in x (east), y (north), z (up): the axes of a 3D case; a 2D case
takes its section by z = 0, so the ``offset`` of the body or a DEM whose profile lies along
z = 0 is needed there.
"""

from pathlib import Path

import numpy as np

HEADER_KEYS = ("ncols", "nrows", "cellsize")


def read_esri_ascii(path):
    """Read an ESRI ASCII grid: (x of the columns, y of the rows, z (nrows, ncols), nodata).

    ``x`` runs east from the first column's centre, ``y`` north from the southern row's
    centre; ``z[i, j]`` is the elevation at (x[j], y[i]), the southern row first, NaN where
    the raster has no data. A malformed file raises ValueError naming the file and what is
    wrong.
    """
    path = Path(path)
    text = path.read_text().split("\n")
    header = {}
    line = 0
    while line < len(text):
        words = text[line].split()
        if not words:
            line += 1
            continue
        key = words[0].lower()
        if key not in ("ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter",
                       "cellsize", "nodata_value"):
            break
        if len(words) != 2:
            raise ValueError(f"{path}: header line {line + 1} '{text[line].strip()}' must be "
                             "a key and one number")
        try:
            header[key] = float(words[1])
        except ValueError:
            raise ValueError(f"{path}: header line {line + 1}: '{words[1]}' is not a "
                             "number") from None
        line += 1
    for key in HEADER_KEYS:
        if key not in header:
            raise ValueError(f"{path}: the header lacks '{key}' (an ESRI ASCII grid has "
                             "ncols, nrows, xllcorner or xllcenter, yllcorner or yllcenter, "
                             "cellsize and optionally NODATA_value)")
    if ("xllcorner" in header) == ("xllcenter" in header) or \
            ("yllcorner" in header) == ("yllcenter" in header):
        raise ValueError(f"{path}: the header needs one of xllcorner, xllcenter and one of "
                         "yllcorner, yllcenter")
    ncols, nrows, size = header["ncols"], header["nrows"], header["cellsize"]
    if ncols != int(ncols) or nrows != int(nrows) or ncols < 2 or nrows < 2:
        raise ValueError(f"{path}: ncols = {ncols:g}, nrows = {nrows:g} must be whole numbers "
                         "of at least 2 (a surface needs two rows and two columns of points)")
    if not size > 0:
        raise ValueError(f"{path}: cellsize = {size:g} must be positive")
    ncols, nrows = int(ncols), int(nrows)
    try:
        values = np.array(" ".join(text[line:]).split(), dtype=float)
    except ValueError as exc:
        raise ValueError(f"{path}: an elevation is not a number ({exc})") from None
    if values.size != ncols * nrows:
        raise ValueError(f"{path}: {values.size} elevations after the header, expected "
                         f"nrows x ncols = {nrows} x {ncols} = {nrows * ncols}")
    z = values.reshape(nrows, ncols)[::-1].copy()
    nodata = header.get("nodata_value")
    if nodata is not None:
        z[z == nodata] = np.nan
    if not np.all(np.isfinite(z) | np.isnan(z)):
        raise ValueError(f"{path}: an elevation is infinite")
    half = 0.0 if "xllcenter" in header else 0.5 * size
    x0 = header.get("xllcenter", header.get("xllcorner", 0.0)) + half
    half = 0.0 if "yllcenter" in header else 0.5 * size
    y0 = header.get("yllcenter", header.get("yllcorner", 0.0)) + half
    return x0 + size * np.arange(ncols), y0 + size * np.arange(nrows), z, nodata


def dem_triangles(x, y, z):
    """Two triangles per square of four points with data: (n, 3, 3) corners, counter-clockwise
    seen from above (their normals point up)."""
    triangles = []
    for i in range(len(y) - 1):
        for j in range(len(x) - 1):
            corners = [(x[j], y[i], z[i, j]), (x[j + 1], y[i], z[i, j + 1]),
                       (x[j + 1], y[i + 1], z[i + 1, j + 1]), (x[j], y[i + 1], z[i + 1, j])]
            if any(np.isnan(c[2]) for c in corners):
                continue
            triangles.append([corners[0], corners[1], corners[2]])
            triangles.append([corners[0], corners[2], corners[3]])
    return np.array(triangles, dtype=float).reshape(-1, 3, 3)


def write_stl(path, triangles, name="dem"):
    """Write triangles (n, 3, 3) as an ASCII STL file."""
    lines = [f"solid {name}"]
    for tri in triangles:
        normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        length = np.linalg.norm(normal)
        normal = normal / length if length > 0 else normal
        lines.append(f"  facet normal {normal[0]:.9e} {normal[1]:.9e} {normal[2]:.9e}")
        lines.append("    outer loop")
        for corner in tri:
            lines.append(f"      vertex {corner[0]:.12e} {corner[1]:.12e} {corner[2]:.12e}")
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    Path(path).write_text("\n".join(lines) + "\n")


def dem_to_stl(dem, out):
    """Convert an ESRI ASCII grid to an STL surface; returns (triangles, x range, y range,
    z range, squares left out for NODATA)."""
    x, y, z, _ = read_esri_ascii(dem)
    triangles = dem_triangles(x, y, z)
    if len(triangles) == 0:
        raise ValueError(f"{dem}: no square of four points with data: no surface to write")
    write_stl(out, triangles, name=Path(dem).stem)
    squares = (len(x) - 1) * (len(y) - 1)
    return (len(triangles), (x[0], x[-1]), (y[0], y[-1]),
            (float(np.nanmin(z)), float(np.nanmax(z))), squares - len(triangles) // 2)
