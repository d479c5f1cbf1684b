"""Command line: python -m mpm_post {summary,energy,field,profile} RUN_DIR ...

Run from the repository root with ``PYTHONPATH=postproc .venv/bin/python -m mpm_post ...``.
Exit codes: 0 success, 1 error (missing or unreadable run), 2 bad command line.
"""

import argparse
import sys

import numpy as np

from . import __version__
from .energy import energy_drift, plot_energy
from .io import list_outputs, load_history, load_particles
from .profiles import (bin_edges, free_surface, height_at_wall, load_reference_profile,
                       particle_half_size, rms_height_difference, toe_position)

STRESS_COMPONENTS = {4: ["xx", "yy", "zz", "xy"], 6: ["xx", "yy", "zz", "xy", "yz", "zx"]}
VECTOR_COMPONENTS = ["x", "y", "z"]


def _component_names(name, array):
    """Labels of the columns of one particle field."""
    if array.ndim == 1:
        return [name]
    ncol = array.shape[1]
    if name in ("stress", "strain") and ncol in STRESS_COMPONENTS:
        return STRESS_COMPONENTS[ncol]
    if ncol == 3:
        return VECTOR_COMPONENTS
    return [str(i) for i in range(ncol)]


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
    if "kinetic_energy" in history:
        print(f"final kinetic energy [J]: {history['kinetic_energy'][-1]:.6e}", file=out)
    print(f"energy drift: {energy_drift(history):.3e}", file=out)
    return 0


def cmd_energy(args, out):
    history = load_history(args.run_dir)
    if history["time"].size == 0:
        raise ValueError(f"history of {args.run_dir} is empty: nothing to plot")
    path = plot_energy(history, args.out)
    print(f"wrote {path}", file=out)
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
    for label, column in zip(_component_names(args.field, array), columns.T):
        if column.size:
            print(f"{label:>10} {column.min():14.6e} {column.max():14.6e} {column.mean():14.6e}",
                  file=out)
        else:
            print(f"{label:>10} {'-':>14} {'-':>14} {'-':>14}", file=out)
    return 0


def cmd_profile(args, out):
    data = load_particles(args.run_dir, time=args.time)
    dim = data["dimension"] or 2
    position = data["position"]
    # the deposit along x; the vertical is y in 2D and z in 3D (docs/output.md)
    x, y = position[:, 0], position[:, 1 if dim == 2 else 2]
    if args.half_size is not None:
        half = np.full(x.size, args.half_size)
    elif "volume" in data:
        half = particle_half_size(data["volume"], dim)
    else:
        raise ValueError(f"{data['path']} has no particle volume: give --half-size")
    if x.size == 0:
        raise ValueError(f"{data['path']} holds no particle")
    toe = toe_position(x, y, half, min_height=args.min_height)
    wall = height_at_wall(x, y, half, x_wall=args.wall)
    print(f"profile at time {data['time']:g} s (step {data['step']}), {x.size} particles, "
          f"file {data['path']}", file=out)
    print(f"toe [m]: {toe:.6g}", file=out)
    print(f"height at wall [m]: {wall:.6g}", file=out)
    if args.reference:
        width = args.bin_width if args.bin_width else 2.0 * float(np.median(half))
        edges = bin_edges(min(args.wall, float(np.min(x - half))), float(np.max(x + half)),
                          width)
        centres, height = free_surface(x, y, half, edges)
        x_ref, h_ref = load_reference_profile(args.reference)
        rms, max_abs = rms_height_difference(centres, height, x_ref, h_ref)
        print(f"reference: {args.reference} ({x_ref.size} points)", file=out)
        print(f"reference toe [m]: {float(np.max(x_ref)):.6g}", file=out)
        print(f"RMS height difference [m]: {rms:.6g}", file=out)
        print(f"max height difference [m]: {max_abs:.6g}", file=out)
    return 0


def build_parser():
    parser = argparse.ArgumentParser(
        prog="python -m mpm_post", description="Summarise and plot mpm-geo run outputs.")
    parser.add_argument("--version", action="version", version=f"mpm_post {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True

    summary = commands.add_parser("summary", help="outputs, particles, final energies, drift")
    summary.add_argument("run_dir", metavar="RUN_DIR", help="run directory, e.g. outputs/base_case")
    summary.set_defaults(func=cmd_summary)

    energy = commands.add_parser("energy", help="plot the energy history")
    energy.add_argument("run_dir", metavar="RUN_DIR")
    energy.add_argument("--out", default="figs/energy.png",
                        help="image file to write (default: figs/energy.png)")
    energy.set_defaults(func=cmd_energy)

    field = commands.add_parser("field", help="min/max/mean of one particle field")
    field.add_argument("run_dir", metavar="RUN_DIR", help="run directory or particles_*.h5 file")
    field.add_argument("--field", default="stress", help="dataset name (default: stress)")
    field.add_argument("--time", type=float, default=None,
                       help="time [s]; the nearest output is used (default: the last one)")
    field.set_defaults(func=cmd_field)

    profile = commands.add_parser(
        "profile", help="toe, height at the wall, RMS difference to a reference surface")
    profile.add_argument("run_dir", metavar="RUN_DIR", help="run directory or particles_*.h5 file")
    profile.add_argument("--time", type=float, default=None,
                         help="time [s]; the nearest output is used (default: the last one)")
    profile.add_argument("--reference", default=None,
                         help="two-column file x [m], height [m] of a measured free surface")
    profile.add_argument("--min-height", type=float, default=0.0,
                         help="deposit thinner than this [m] is not counted in the toe "
                              "(default 0)")
    profile.add_argument("--wall", type=float, default=0.0,
                         help="x of the wall the deposit rests against [m] (default 0)")
    profile.add_argument("--bin-width", type=float, default=None,
                         help="bin width of the free surface [m] (default: the particle size)")
    profile.add_argument("--half-size", type=float, default=None,
                         help="particle half-size [m] (default: from the particle volumes)")
    profile.set_defaults(func=cmd_profile)
    return parser


def main(argv=None, out=None):
    """Run one command; returns the exit code."""
    out = sys.stdout if out is None else out
    args = build_parser().parse_args(argv)
    try:
        return args.func(args, out)
    except (OSError, ValueError, KeyError) as exc:
        message = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"mpm_post: error: {message}", file=sys.stderr)
        return 1
