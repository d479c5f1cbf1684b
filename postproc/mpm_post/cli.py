"""Command line: python -m mpm_post {summary,energy,field,profile,error,pore,plot} ...

Run from the repository root with ``PYTHONPATH=postproc .venv/bin/python -m mpm_post ...``;
docs/postproc.md describes every command.
Exit codes: 0 success; 1 the run or a file cannot answer (missing or unreadable, a field or
component it does not hold, no output at the requested time, an exact field that is not finite
there); 2 bad command line (unknown command or option, an invalid --exact expression, a --time
before the first or after the last output of the run; for ``pore``, also a folder that does not
exist or holds no output, an output without pore_pressure, a --vertical-axis the run does not
have).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from . import __version__
from .energy import describe_drift, energy_balance, energy_unit, plot_run_energy
from .errors import (FIELD_UNITS, NORMS, WEIGHTS, ExpressionError, compile_expression,
                     particle_error)
from .io import (TimeOutsideRunError, component_names, list_outputs, load_history,
                 load_particles, load_terrain, output_at)
from .pore import (AXES, PoreInputError, default_heights, load_pore_pressure, nearest_particles,
                   plot_pore_pressure)
from .profiles import (height_at_wall, load_reference_profile, max_height, particle_half_size,
                       particle_size, rms_height_difference, surface_profile, terrain_height,
                       toe_position)

NORM_LABELS = {"l1": "L1", "l2": "L2", "linf": "Linf"}


def _format_times(times, shown=6):
    if len(times) <= shown:
        return " ".join(f"{t:g}" for t in times)
    head = " ".join(f"{t:g}" for t in times[: shown // 2])
    tail = " ".join(f"{t:g}" for t in times[-(shown // 2):])
    return f"{head} ... {tail}"


def cmd_summary(args, out):
    outputs = list_outputs(args.run_dir)
    print(f"run: {args.run_dir}", file=out)
    print(f"outputs: {len(outputs)}", file=out)
    if outputs:
        times = [t for t, _ in outputs]
        print(f"times [s]: {_format_times(times)}", file=out)
        last = load_particles(outputs[-1][1])
        if last["case_name"]:
            print(f"case: {last['case_name']}", file=out)
        if last["dimension"]:
            print(f"dimension: {last['dimension']}", file=out)
        print(f"particles: {last['position'].shape[0]}", file=out)
        print(f"last output: step {last['step']}, time {last['time']:g} s", file=out)
    try:
        history = load_history(args.run_dir)
    except FileNotFoundError:
        print("history: no history.csv", file=out)
        return 0
    if history["time"].size == 0:
        print("history: empty", file=out)
        return 0
    unit = energy_unit(last["dimension"] if outputs else 0)
    if "kinetic_energy" in history:
        print(f"final kinetic energy [{unit}]: {history['kinetic_energy'][-1]:.6e}", file=out)
    if "total" in history:
        print(f"energy drift: {describe_drift(energy_balance(history), unit)}", file=out)
    else:
        print(f"energy drift: not available (history.csv has no 'total' column; columns: "
              f"{', '.join(history)})", file=out)
    return 0


def cmd_energy(args, out):
    """``energy`` and ``plot energy``: the one energy figure (energy.plot_run_energy)."""
    path, drift = plot_run_energy(args.run_dir, args.out)
    print(f"wrote {path}", file=out)
    if drift is not None:
        print(f"energy drift: {drift}", file=out)
    return 0


def cmd_field(args, out):
    data = load_particles(args.run_dir, time=args.time)
    fields = sorted(k for k, v in data.items() if isinstance(v, np.ndarray))
    if args.field not in fields:
        raise KeyError(f"no field '{args.field}' in {data['path']} (fields: {', '.join(fields)})")
    array = np.asarray(data[args.field], dtype=float)
    print(f"{args.field} at time {data['time']:g} s (step {data['step']}), "
          f"{array.shape[0]} particles, file {data['path']}", file=out)
    columns = array.reshape(array.shape[0], -1)
    print(f"{'component':>10} {'min':>14} {'max':>14} {'mean':>14}", file=out)
    for label, column in zip(component_names(args.field, array), columns.T):
        if column.size:
            print(f"{label:>10} {column.min():14.6e} {column.max():14.6e} {column.mean():14.6e}",
                  file=out)
        else:
            print(f"{label:>10} {'-':>14} {'-':>14} {'-':>14}", file=out)
    return 0


def _first_output(args, data):
    """The first output of the run ``data`` belongs to; ``data`` itself for a single file."""
    if Path(args.run_dir).is_file():
        return data
    outputs = list_outputs(args.run_dir)
    if not outputs or outputs[0][0] >= data["time"]:
        return data
    return load_particles(outputs[0][1])


def _half_sizes(args, data):
    """Particle half-sizes [m] of an output: --half-size, or from the particle volumes."""
    if args.half_size is not None:
        return np.full(data["position"].shape[0], args.half_size)
    if "volume" in data:
        return particle_half_size(data["volume"], data["dimension"] or 2)
    raise ValueError(f"{data['path']} has no particle volume: give --half-size")


def _floor(args, first):
    """(floor, description): floor(position, top) is the floor under each particle [m].

    The vertical is y in 2D and z in 3D (docs/output.md). --floor names it; else in 3D the
    terrain of the run when it has one (terrain.h5), or the lowest particle bottom of the first
    output; in 2D y = 0.
    """
    dim = first["dimension"] or 2
    axis = "y" if dim == 2 else "z"
    if args.floor is not None:
        return (lambda position, top: np.full(position.shape[0], args.floor),
                f"{axis} = {args.floor:g} m (--floor)")
    if dim == 3:
        corners = load_terrain(args.run_dir)
        if corners is not None:
            return (lambda position, top: terrain_height(position[:, 0], position[:, 1],
                                                         corners, below=top),
                    "the terrain (terrain.h5), straight below each particle")
        if first["position"].shape[0]:
            bottom = float(np.min(first["position"][:, 2] - _half_sizes(args, first)))
            return (lambda position, top: np.full(position.shape[0], bottom),
                    f"z = {bottom:.6g} m, the lowest particle bottom at t = {first['time']:g} s "
                    "(--floor to change)")
    return (lambda position, top: np.zeros(position.shape[0]),
            f"{axis} = 0 (--floor to change)")


def _deposit(args, data, floor):
    """Particle x, height above the floor and half-size [m] of an output, for the profiles.

    The deposit runs along x. Returns ``(x, height, half, left_out)``: ``left_out`` particles
    have no floor under them (beyond the terrain in plan view) and are not in the arrays.
    """
    dim = data["dimension"] or 2
    position = data["position"]
    if position.shape[0] == 0:
        raise ValueError(f"{data['path']} holds no particle")
    half = _half_sizes(args, data)
    vertical = position[:, 1 if dim == 2 else 2]
    height = vertical - floor(position, vertical + half)
    kept = np.isfinite(height)
    if not np.any(kept):
        raise ValueError(f"{data['path']}: no particle lies above the terrain")
    return position[kept, 0], height[kept], half[kept], int(np.count_nonzero(~kept))


def _surface(args, x, y, half):
    """The free surface (bin centres, heights, bin width) [m] from the wall to the furthest
    particle, on bins no narrower than the particle size."""
    return surface_profile(x, y, half, min(args.wall, float(np.min(x - half))),
                           float(np.max(x + half)), args.bin_width)


def _profile_inputs(args):
    """The output of --time, its first output, the floor and the deposit of the output."""
    data = load_particles(args.run_dir, time=args.time)
    first = _first_output(args, data)
    floor, datum = _floor(args, first)
    return data, first, floor, datum, _deposit(args, data, floor)


def cmd_profile(args, out):
    data, first, floor, datum, (x, y, half, left_out) = _profile_inputs(args)
    toe = toe_position(x, y, half, min_height=args.min_height)
    print(f"profile at time {data['time']:g} s (step {data['step']}), {x.size} particles, "
          f"file {data['path']}", file=out)
    print(f"heights above: {datum}", file=out)
    if left_out:
        print(f"left out: {left_out} particles beyond the terrain (no floor under them)",
              file=out)
    print(f"toe [m]: {toe:.6g}", file=out)
    # The wall holds the deposit only when the mass started against it: a slide that starts
    # away from x = --wall has no height at the wall, which a 0 would misreport.
    x0, y0, half0, _ = _deposit(args, first, floor)
    reach = particle_size(half0)
    if float(np.min(x0 - half0)) <= args.wall + reach:
        print(f"height at wall [m]: {height_at_wall(x, y, half, x_wall=args.wall):.6g}",
              file=out)
    else:
        print(f"height at wall: does not apply (no particle within {reach:.3g} m of the wall "
              f"x = {args.wall:g} m at t = {first['time']:g} s; --wall X names another)",
              file=out)
    print(f"max height [m]: {max_height(x, y, half, x_max=toe):.6g}", file=out)
    if first is not data:
        toe0 = toe_position(x0, y0, half0, min_height=args.min_height)
        print(f"runout from t = {first['time']:g} s [m]: {toe - toe0:.6g} "
              f"(toe then {toe0:.6g})", file=out)
    if args.reference:
        centres, height, width = _surface(args, x, y, half)
        x_ref, h_ref = load_reference_profile(args.reference)
        rms, max_abs = rms_height_difference(centres, height, x_ref, h_ref)
        print(f"free surface: {centres.size} bins of {width:.3g} m", file=out)
        print(f"reference: {args.reference} ({x_ref.size} points)", file=out)
        print(f"reference toe [m]: {float(np.max(x_ref)):.6g}", file=out)
        print(f"RMS height difference [m]: {rms:.6g}", file=out)
        print(f"max height difference [m]: {max_abs:.6g}", file=out)
    return 0


def cmd_error(args, out):
    exact = compile_expression(args.exact)  # before reading: a bad expression is exit code 2
    time, path = output_at(args.run_dir, args.time, args.time_tol)
    data = load_particles(path)
    norms = particle_error(data, args.field, args.component, exact, weight=args.weight,
                           scale=args.scale, coordinates=args.coordinates)
    unit = FIELD_UNITS.get(args.field, "")
    name = args.field if args.component in (None, args.field) else \
        f"{args.field} {args.component}"
    print(f"{name} at time {time:g} s (step {data['step']}), {norms.count} particles, "
          f"file {path}", file=out)
    print(f"exact: {args.exact} (at the {args.coordinates} positions)", file=out)
    source = "--scale" if args.scale is not None else "max |exact|"
    print(f"weights: {args.weight}; scale [{unit}]: {norms.scale:.6e} ({source})", file=out)
    print(f"{'norm':>6} {'absolute [' + unit + ']':>16} {'relative':>14}", file=out)
    for norm in NORMS if args.norm == "all" else [args.norm]:
        print(f"{NORM_LABELS[norm]:>6} {norms.absolute(norm):16.6e} "
              f"{norms.relative(norm):14.6e}", file=out)
    return 0


def cmd_pore(args, out):
    """``pore``: pore pressure profiles at every output and at a few heights against time."""
    history = load_pore_pressure(args.run_dir, args.vertical_axis)
    axis, first = history.axis, history.height[0]
    if args.depths:
        targets, chosen = list(args.depths), "--depths"
    else:
        targets = default_heights(first)
        chosen = (f"1/4, 1/2 and 3/4 of the particles' extent {axis} = {first.min():.6g} .. "
                  f"{first.max():.6g} m at t = {history.time[0]:g} s")
    particles = nearest_particles(first, targets)
    path = plot_pore_pressure(args.out, history, particles, targets,
                              title=f"{history.case_name}: pore pressure (compression "
                                    "positive)")
    t0, t1 = history.time[0], history.time[-1]
    print(f"wrote {path}", file=out)
    print(f"pore pressure of {first.size} particles at {history.time.size} outputs, t = "
          f"{t0:g} .. {t1:g} s; heights along {axis}: {chosen}", file=out)
    for target, index in zip(targets, particles):
        pressure = history.pressure[:, index] / 1.0e3
        print(f"{axis} = {target:.6g} m: particle {index} (at {axis} = {first[index]:.6g} m), "
              f"pore pressure {pressure[0]:.6g} kPa at t = {t0:g} s, {pressure[-1]:.6g} kPa "
              f"at t = {t1:g} s", file=out)
    return 0


def cmd_plot_profile(args, out):
    from .plots import plot_profile

    data, _, _, datum, (x, y, half, _) = _profile_inputs(args)
    centres, height, _ = _surface(args, x, y, half)
    toe = toe_position(x, y, half, min_height=args.min_height)
    reference, title = None, f"t = {data['time']:g} s: toe {toe:.4g} m"
    if args.reference:
        reference = load_reference_profile(args.reference)
        rms, _ = rms_height_difference(centres, height, *reference)
        title += f", RMS height difference {rms:.3g} m"
    path = plot_profile(args.out, centres, height, reference=reference, particles=(x, y),
                        toe=toe, title=f"{title}\nheights above {datum}")
    print(f"wrote {path}", file=out)
    return 0


def cmd_plot_convergence(args, out):
    from .plots import load_convergence, plot_convergence

    h, errors, labels = load_convergence(args.table)
    path, orders = plot_convergence(args.out, h, errors, labels, slopes=args.slopes,
                                    title=args.title, ylabel=args.ylabel)
    print(f"wrote {path}", file=out)
    for label, (slope, sigma) in orders.items():
        count = sum(1 for other in labels if other == label)
        shown = "-" if np.isnan(slope) else f"{slope:.3f}"
        if not np.isnan(sigma):
            shown += f" +- {sigma:.3f}"
        print(f"{label or 'error'}: order {shown} ({count} points)", file=out)
    return 0


def cmd_plot_cost(args, out):
    from .plots import load_costs, plot_error_vs_time

    labels, errors, wall = load_costs(args.table)
    path, front = plot_error_vs_time(args.out, labels, errors, wall, title=args.title,
                                     ylabel=args.ylabel)
    print(f"wrote {path}", file=out)
    print("Pareto front (label, error, run time [s]):", file=out)
    for i in front:
        print(f"  {labels[i]}, {errors[i]:.6g}, {wall[i]:.6g}", file=out)
    return 0


def cmd_plot_load_displacement(args, out):
    from .plots import load_displacement, plot_load_displacement

    try:
        history = load_history(args.run)
        displacement, load, region, axis = load_displacement(history, args.region, args.axis,
                                                             args.width)
    except (OSError, ValueError) as exc:
        print(f"mpm_post: error: {exc}", file=sys.stderr)
        return 1
    if load.size == 0:
        print(f"mpm_post: error: {args.run}: the history has no line yet", file=sys.stderr)
        return 1
    unit = "Pa (N/m2 in 3D: per area)" if args.width else "N (N/m in 2D)"
    ylabel = "pressure [Pa]" if args.width else "load [N; N/m in 2D]"
    reference = None if args.reference is None else (args.reference, "reference")
    path = plot_load_displacement(args.out, displacement, load,
                                  title=f"region {region}, along {axis}", reference=reference,
                                  ylabel=ylabel)
    peak = int(np.argmax(load))
    print(f"wrote {path}", file=out)
    print(f"region {region} along {axis}: largest load {load[peak]:.6g} {unit} at "
          f"displacement {displacement[peak]:.6g} m; last {load[-1]:.6g} at "
          f"{displacement[-1]:.6g} m", file=out)
    return 0


def cmd_dem_to_stl(args, out):
    from .dem import dem_to_stl

    count, xr, yr, zr, left = dem_to_stl(args.dem, args.out)
    print(f"wrote {args.out}: {count} triangles, x {xr[0]:.6g} .. {xr[1]:.6g} m, "
          f"y {yr[0]:.6g} .. {yr[1]:.6g} m, z {zr[0]:.6g} .. {zr[1]:.6g} m"
          + (f"; {left} squares without data left out" if left else ""), file=out)
    return 0


def cmd_plot_strength_reduction(args, out):
    from .plots import load_strength_reduction, factor_of_safety, plot_strength_reduction

    try:
        trials = load_strength_reduction(args.run)
    except (OSError, ValueError, KeyError) as exc:
        print(f"mpm_post: error: {exc}", file=sys.stderr)
        return 1
    reference = None if args.reference is None else (args.reference, "reference")
    path = plot_strength_reduction(args.out, trials, limit=args.limit, reference=reference,
                                   title="strength reduction")
    holds, fails = factor_of_safety(trials)
    print(f"wrote {path}", file=out)
    if holds is None:
        print(f"fails at every factor tried (from {fails:.6g}): the factor of safety is below",
              file=out)
    elif fails is None:
        print(f"holds at every factor tried (up to {holds:.6g}): the factor of safety is above",
              file=out)
    else:
        print(f"factor of safety {0.5 * (holds + fails):.4g} (holds at {holds:.6g}, fails at "
              f"{fails:.6g}; {len(trials['factor'])} trials)", file=out)
    return 0


def _positive(text):
    """argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{text}'") from None
    if not (np.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _finite(text):
    """argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: '{text}'") from None
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text}")
    return value


def _profile_options(parser):
    parser.add_argument("run_dir", metavar="RUN_DIR", help="run directory or particles_*.h5 file")
    parser.add_argument("--time", type=float, default=None,
                        help="time [s]; the nearest output is used (default: the last "
                             "one); a time outside the run's outputs is an error")
    parser.add_argument("--reference", default=None,
                        help="two-column file x [m], height [m] of a measured free surface")
    parser.add_argument("--min-height", type=float, default=0.0,
                        help="deposit thinner than this [m] is not counted in the toe "
                             "(default 0)")
    parser.add_argument("--wall", type=float, default=0.0,
                        help="x of the wall the deposit rests against [m] (default 0)")
    parser.add_argument("--bin-width", type=_positive, default=None,
                        help="bin width of the free surface [m] (default and least: the "
                             "particle size)")
    parser.add_argument("--floor", type=float, default=None,
                        help="vertical coordinate [m] the heights are measured from (default: "
                             "y = 0 in 2D; in 3D the terrain, or the lowest particle bottom at "
                             "the first output)")
    parser.add_argument("--half-size", type=float, default=None,
                        help="particle half-size [m] (default: from the particle volumes)")


def _energy_options(parser):
    """``energy`` and ``plot energy``: one command under two names."""
    parser.add_argument("run_dir", metavar="RUN_DIR", help="run directory or history.csv")
    parser.add_argument("--out", default="figs/energy.png",
                        help="image file to write (default: figs/energy.png)")
    parser.set_defaults(func=cmd_energy)


def build_parser():
    parser = argparse.ArgumentParser(
        prog="python -m mpm_post", description="Summarise and plot mpm-geo run outputs.",
        epilog="Exit codes: 0 success, 1 the run or a file cannot answer, 2 bad command line, "
               "--exact expression, a --time outside the run's outputs or (pore) a run without "
               "pore pressure. 'COMMAND --help' for each command; docs/postproc.md.")
    parser.add_argument("--version", action="version", version=f"mpm_post {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    summary = commands.add_parser("summary", help="outputs, particles, final energies, drift")
    summary.add_argument("run_dir", metavar="RUN_DIR", help="run directory, e.g. outputs/base_case")
    summary.set_defaults(func=cmd_summary)

    _energy_options(commands.add_parser(
        "energy", help="plot the energy history (the same figure as 'plot energy')"))

    field = commands.add_parser("field", help="min/max/mean of one particle field")
    field.add_argument("run_dir", metavar="RUN_DIR", help="run directory or particles_*.h5 file")
    field.add_argument("--field", default="stress", help="dataset name (default: stress)")
    field.add_argument("--time", type=float, default=None,
                       help="time [s]; the nearest output is used (default: the last "
                            "one); a time outside the run's outputs is an error")
    field.set_defaults(func=cmd_field)

    profile = commands.add_parser(
        "profile", help="runout (toe), deposit heights, RMS difference to a reference surface")
    _profile_options(profile)
    profile.set_defaults(func=cmd_profile)

    error = commands.add_parser(
        "error", help="L1, L2, Linf norms of a particle field against an exact field")
    error.add_argument("run_dir", metavar="RUN_DIR", help="run directory or particles_*.h5 file")
    error.add_argument("--field", required=True,
                       help="particle field: position, displacement, velocity, stress, ...")
    error.add_argument("--component", default=None,
                       help="x, y, z or magnitude for vectors; xx, yy, zz, xy (yz, zx) for "
                            "stress and strain; omit for a one-value field")
    error.add_argument("--exact", required=True, metavar="EXPR",
                       help="exact field, a NumPy expression in x, y, z [m] and t [s], "
                            "e.g. '-2650*9.81*(0.1-y)'")
    error.add_argument("--time", type=float, default=None,
                       help="time [s] of the output to compare (default: the last one)")
    error.add_argument("--time-tol", type=_positive, default=None, metavar="DT",
                       help="largest distance [s] between --time and an output time "
                            "(default: 1e-3 of the last output time)")
    error.add_argument("--norm", choices=list(NORMS) + ["all"], default="all",
                       help="norm to print (default: all)")
    error.add_argument("--weight", choices=WEIGHTS, default="mass",
                       help="particle weights of the L1 and L2 norms (default: mass)")
    error.add_argument("--scale", type=_positive, default=None,
                       help="value the relative norms divide by (default: max |exact|)")
    error.add_argument("--coordinates", choices=["current", "initial"], default="current",
                       help="evaluate the exact field at the current positions, or at the "
                            "initial ones, position - displacement (default: current)")
    error.set_defaults(func=cmd_error)

    pore = commands.add_parser(
        "pore", help="pore pressure against height at every output and against time at a few "
                     "heights (cases with pore_water)")
    pore.add_argument("run_dir", metavar="OUTPUT_DIR", help="run directory, e.g. outputs/<case>")
    pore.add_argument("--out", default="figs/pore_pressure.png",
                      help="image file to write (default: figs/pore_pressure.png)")
    pore.add_argument("--vertical-axis", choices=list(AXES), default=None,
                      help="the vertical coordinate, the heights (default: y in 2D, z in 3D)")
    pore.add_argument("--depths", type=_finite, nargs="+", default=None, metavar="H",
                      help="heights [m] (values of the vertical coordinate) to follow in time: "
                           "the particle nearest to each at the first output (default: 1/4, 1/2 "
                           "and 3/4 of the particles' vertical extent then). The profiles "
                           "average the particles of one height (rounded to 1e-9 m).")
    pore.set_defaults(func=cmd_pore)

    dem = commands.add_parser(
        "dem-to-stl", help="a DEM raster (ESRI ASCII grid) as an STL surface, for a layer's "
                           "top or bottom or contact.file")
    dem.add_argument("dem", metavar="DEM", help="ESRI ASCII grid (.asc), northern row first")
    dem.add_argument("--out", required=True, help="STL file to write")
    dem.set_defaults(func=cmd_dem_to_stl)

    plot = commands.add_parser("plot", help="write a standard figure (PNG)")
    plots = plot.add_subparsers(dest="figure", metavar="FIGURE")
    plots.required = True
    profile_figure = plots.add_parser(
        "profile", help="free surface of a run against a reference profile")
    _profile_options(profile_figure)
    profile_figure.add_argument("--out", default="figs/profile.png",
                              help="image file to write (default: figs/profile.png)")
    profile_figure.set_defaults(func=cmd_plot_profile)

    _energy_options(plots.add_parser("energy", help="energy balance from history.csv"))

    curve = plots.add_parser(
        "load-displacement", help="load against displacement of a prescribed_motion region")
    curve.add_argument("run", help="run folder (or its history.csv)")
    curve.add_argument("--region", default=None,
                       help="name of the region (default: the only one of the run)")
    curve.add_argument("--axis", choices=["x", "y", "z"], default=None,
                       help="component (default: the vertical, the last axis)")
    curve.add_argument("--width", type=_positive, default=None,
                       help="width [m] (2D) or area [m2] (3D) to divide the load by: a pressure")
    curve.add_argument("--reference", type=float, default=None,
                       help="a reference load (e.g. a bearing capacity), drawn as a line")
    curve.add_argument("--out", default="figs/load_displacement.png",
                       help="image file to write (default: figs/load_displacement.png)")
    curve.set_defaults(func=cmd_plot_load_displacement)

    reduction = plots.add_parser(
        "strength-reduction", help="displacement against the factor of a strength reduction")
    reduction.add_argument("run", help="folder of the analysis (or its strength_reduction.csv)")
    reduction.add_argument("--limit", type=_positive, default=None,
                           help="the displacement limit of the case [m], drawn as a line")
    reduction.add_argument("--reference", type=_positive, default=None,
                           help="a reference factor of safety, drawn as a line")
    reduction.add_argument("--out", default="figs/strength_reduction.png",
                           help="image file to write (default: figs/strength_reduction.png)")
    reduction.set_defaults(func=cmd_plot_strength_reduction)

    for name, func, table, default, helptext in [
            ("convergence", cmd_plot_convergence, "h,error[,label]", "figs/convergence.png",
             "error against cell size, log-log, with fitted orders"),
            ("cost", cmd_plot_cost, "label,error,wall_time", "figs/error_time.png",
             "error against run time, log-log, with the Pareto front")]:
        figure = plots.add_parser(name, help=helptext)
        figure.add_argument("table", metavar="CSV", help=f"CSV file, lines {table} (header "
                                                         "line optional)")
        figure.add_argument("--out", default=default,
                            help=f"image file to write (default: {default})")
        figure.add_argument("--title", default=None, help="title of the plot")
        figure.add_argument("--ylabel", default="error", help="label of the error axis")
        if name == "convergence":
            figure.add_argument("--slopes", type=float, nargs="*", default=[1.0, 2.0],
                                metavar="P", help="orders of the reference lines "
                                                  "(default: 1 2)")
        figure.set_defaults(func=func)
    return parser


# Options whose value may start with '-' (an expression such as -2650*9.81*(0.1-y)), which
# argparse would otherwise take for an option.
EXPRESSION_OPTIONS = ("--exact",)


def _join_expression_values(argv):
    """``--exact VALUE`` as ``--exact=VALUE``, so that a VALUE starting with '-' is a value."""
    joined, argv = [], list(argv)
    while argv:
        item = argv.pop(0)
        if item in EXPRESSION_OPTIONS and argv:
            item = f"{item}={argv.pop(0)}"
        joined.append(item)
    return joined


def main(argv=None, out=None):
    """Run one command; returns the exit code."""
    out = sys.stdout if out is None else out
    argv = sys.argv[1:] if argv is None else argv
    args = build_parser().parse_args(_join_expression_values(argv))
    try:
        return args.func(args, out)
    except (ExpressionError, TimeOutsideRunError, PoreInputError) as exc:
        print(f"mpm_post: error: {exc}", file=sys.stderr)
        return 2
    except (OSError, ValueError, KeyError) as exc:
        message = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"mpm_post: error: {message}", file=sys.stderr)
        return 1
