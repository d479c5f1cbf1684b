"""Synthetic DEM of a slope, as STL: the terrain and a soil mass on it (inputs/landslide_terrain.json).

usage: python scripts/make_terrain.py [--out data]

The terrain is a height field z_t(x, y) over [0, 6] x [0, 2] m: a plateau at about 2.0 m that
falls along x to a valley floor at 0.3 m (a tanh profile, steepest 47 deg at x = 2.5 m), with a
gentle cross-slope undulation, sampled every 0.1 m like a DEM raster and written as 2 triangles
per raster cell (data/terrain.stl, binary, normals up). The soil mass is a closed surface over
[1.2, 2.6] x [0.5, 1.5] m: its base follows the terrain 2 cm above it (the particles start just
off the surface), its top 0.35 m above the terrain (data/soil_mass.stl, outward normals).
"""

import argparse
import os
import struct

import numpy as np


def terrain_height(x, y):
    """Height of the terrain [m] at (x, y)."""
    return 0.3 + 0.85 * (1.0 - np.tanh((x - 2.5) / 0.8)) + 0.05 * np.sin(np.pi * y) * (x < 4.0)


def write_stl(path, triangles, header):
    """Binary STL of an (n, 3, 3) array of triangles (corner, coordinate)."""
    triangles = np.asarray(triangles, dtype=np.float64)
    e1 = triangles[:, 1] - triangles[:, 0]
    e2 = triangles[:, 2] - triangles[:, 0]
    normals = np.cross(e1, e2)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    with open(path, "wb") as f:
        f.write(header.encode()[:80].ljust(80, b" "))
        f.write(struct.pack("<I", len(triangles)))
        for n, t in zip(normals, triangles):
            f.write(struct.pack("<12fH", *n, *t[0], *t[1], *t[2], 0))


def grid_triangles(x, y, z):
    """Two triangles per cell of a height field z[i, j] at (x[i], y[j]), normals up."""
    tris = []
    for i in range(len(x) - 1):
        for j in range(len(y) - 1):
            a = (x[i], y[j], z[i, j])
            b = (x[i + 1], y[j], z[i + 1, j])
            c = (x[i + 1], y[j + 1], z[i + 1, j + 1])
            d = (x[i], y[j + 1], z[i, j + 1])
            tris += [(a, b, c), (a, c, d)]
    return tris


def soil_mass(x0, x1, y0, y1, base, thickness, step):
    """Closed surface between base and base + thickness above the terrain over a rectangle."""
    x = np.linspace(x0, x1, int(round((x1 - x0) / step)) + 1)
    y = np.linspace(y0, y1, int(round((y1 - y0) / step)) + 1)
    X, Y = np.meshgrid(x, y, indexing="ij")
    ground = terrain_height(X, Y)
    bottom = ground + base
    top = ground + thickness
    tris = grid_triangles(x, y, top)                                   # up
    tris += [(a, c, b) for a, b, c in grid_triangles(x, y, bottom)]   # down
    # side walls, outward: along y = y0 (normal -y), y = y1 (+y), x = x0 (-x), x = x1 (+x)
    for i in range(len(x) - 1):
        for j, sign in ((0, -1), (len(y) - 1, 1)):
            p = (x[i], y[j], bottom[i, j])
            q = (x[i + 1], y[j], bottom[i + 1, j])
            r = (x[i + 1], y[j], top[i + 1, j])
            s = (x[i], y[j], top[i, j])
            tris += [(p, q, r), (p, r, s)] if sign < 0 else [(p, r, q), (p, s, r)]
    for j in range(len(y) - 1):
        for i, sign in ((0, -1), (len(x) - 1, 1)):
            p = (x[i], y[j], bottom[i, j])
            q = (x[i], y[j + 1], bottom[i, j + 1])
            r = (x[i], y[j + 1], top[i, j + 1])
            s = (x[i], y[j], top[i, j])
            tris += [(p, r, q), (p, s, r)] if sign < 0 else [(p, q, r), (p, r, s)]
    return tris


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="data", help="folder of the STL files (default: data)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    x = np.linspace(0.0, 6.0, 61)
    y = np.linspace(0.0, 2.0, 21)
    X, Y = np.meshgrid(x, y, indexing="ij")
    terrain = grid_triangles(x, y, terrain_height(X, Y))
    write_stl(os.path.join(args.out, "terrain.stl"), terrain,
              "mpm-geo synthetic DEM: slope 2.0 m -> 0.3 m, 0.1 m raster")
    mass = soil_mass(1.2, 2.6, 0.5, 1.5, 0.02, 0.35, 0.1)
    write_stl(os.path.join(args.out, "soil_mass.stl"), mass,
              "mpm-geo soil mass on the synthetic slope, 0.35 m thick")
    print(f"{args.out}/terrain.stl: {len(terrain)} triangles; "
          f"{args.out}/soil_mass.stl: {len(mass)} triangles")


if __name__ == "__main__":
    main()
