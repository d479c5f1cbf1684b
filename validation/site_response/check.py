#!/usr/bin/env python3
"""Validation: 1D site response of an elastic soil column on a compliant base (a seismic face).

A column 20 m high between sliding walls (dx = 0.5 m, 2 x 2 particles per cell, cpGIMP,
MUSL, FLIP), linear elastic, E = 15 MPa, nu = 0.3, rho = 2000 kg/m3: a confined P-wave speed
vp = sqrt(M / rho) = 100.48 m/s. Its base is a compliant seismic face (Joyner and Chen 1975)
whose ground beyond has twice the column's wave speeds (the density of the material at the
face), so the impedance ratio of soil to rock is alpha = 0.5; the record is the outcrop
velocity of that ground, a vertical Ricker wavelet of 3.5 Hz centred at 0.6 s (0.05 m/s peak,
validation/site_response/ricker.csv). No gravity, no damping: the only loss is the radiation
into the base. 8 s are run (the motion has died out by then: a fraction 1/3 of the wave is
reflected back up by the base per round trip of 0.4 s).

Closed form (Kramer 1996, Geotechnical Earthquake Engineering, section 7.2.1, for a uniform
undamped layer on elastic rock; the P-wave form of a laterally confined column, with the
constrained modulus): the surface motion over the outcrop motion is
|H(f)| = 1 / sqrt(cos^2(k H) + alpha^2 sin^2(k H)), k = 2 pi f / vp, with resonances at
f_n = (2 n - 1) vp / (4 H) = 1.256, 3.768, 6.280 Hz where |H| = 1 / alpha = 2.

The script takes the mean vertical velocity of the top particles at every output (written at
the first step after each 0.01 s, so it is put on a uniform 0.01 s grid by linear
interpolation) and the outcrop record on the same grid, zero-pads both to 64 s and divides
their Fourier transforms. Compared at the first three resonances: the amplification |H| at
f_n against 1 / alpha, and the resonance frequency, where the phase of H passes
-(2n - 1) pi / 2 (the phase falls steeply there, by 2 / alpha per radian of k H; the peak of
|H| is too flat at alpha = 0.5 to locate: it is half-power wide over a third of f_1)
against f_n. Bands, gating: the amplification within 5 % (the grid's dispersion at 32 cells
per wavelength of f_3 is 0.2 % of the wave speed, and the dashpot's area is exact for
cpGIMP; what is left is the time integration and the base's explicit input, a few per cent
at most), the resonance frequency within 1 % (the same dispersion, and the column's height,
which the grid sees to a fraction of a particle spacing, 0.25 m of 20 m being 1.25 %). Reported:
the RMS difference of the two amplification curves from 0.5 to 7 Hz, relative to 1 / alpha.
Gating too: the energy residual within 2 % of the work the base did. The error converges:
with 0.25 m cells the amplifications were 2.000, 2.003, 2.008 and the resonances 1.254,
3.766, 6.276 Hz (2026-12-07); at CFL 0.25 instead of 0.5, 2.001, 2.015, 2.038.

S waves (site_response_s.json): the same column with periodic side faces (a laterally
infinite layer: the nodes of the two sides are tied, domain.boundaries "periodic") shaken
horizontally (scale [1, 0]) by the same record: vs = sqrt(G / rho) = 53.71 m/s, the rock's vs
twice it (alpha = 0.5), resonances at f_n = (2n - 1) vs / (4 H) = 0.671, 2.014, 3.357 Hz; the
same closed form with vs, the same bands.

    .venv/bin/python validation/site_response/check.py [--exe build/mpm_geo] [--no-run]

Writes results/metrics.json and results/site_response.png (P waves), results/metrics_s.json
and results/site_response_s.png (S waves).
Exit codes: 0 every target met, 1 a target missed, 2 a run or the analysis failed.
"""

import argparse
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "postproc"))

import h5py  # noqa: E402
import numpy as np  # noqa: E402

from mpm_post import load_history  # noqa: E402
from mpm_post.io import list_outputs  # noqa: E402
from mpm_post.run import run_mpm_geo  # noqa: E402
from mpm_post.validation import (  # noqa: E402
    agg_figure, common_arguments, exe_missing, load_json, relative, target, verdict, write_json)

RESULTS = HERE / "results"
CASE = HERE / "site_response.json"
CASE_S = HERE / "site_response_s.json"
PADDED = 64.0          # s: length of the zero-padded series
AMPLITUDE_BAND = 0.05
FREQUENCY_BAND = 0.01
SAMPLE = 0.01          # s: the uniform grid of the series


def shear(case):
    """Whether the case shakes its base horizontally (S waves)."""
    return case["domain"]["boundaries"]["ymin"]["scale"][0] != 0


def column(case):
    """(H, wave speed of the soil, alpha) of the case: vp and the rock's vp for a vertical
    record, vs and the rock's vs for a horizontal one."""
    soil = case["materials"][0]
    young, nu, rho = soil["E"], soil["nu"], soil["rho"]
    base = case["domain"]["boundaries"]["ymin"]
    height = case["bodies"][0]["max"][1] - case["bodies"][0]["min"][1]
    if shear(case):
        vs = float(np.sqrt(young / (2 * (1 + nu)) / rho))
        return height, vs, vs / base["vs"]
    modulus = young * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    vp = float(np.sqrt(modulus / rho))
    return height, vp, vp / base["vp"]


def outcrop(case, t):
    """The record's velocity at times t (linear between its rows, as the face takes it)."""
    record = np.loadtxt(REPO / case["domain"]["boundaries"]["ymin"]["file"], delimiter=",",
                        skiprows=1)
    scale = case["domain"]["boundaries"]["ymin"]["scale"][0 if shear(case) else 1]
    return scale * np.interp(t, record[:, 0], record[:, 1])


def top_velocity(output, component=1):
    """(times, mean velocity of the top layer of particles along `component`) of every
    output."""
    times, velocity = [], []
    top = None
    for time, path in list_outputs(output):
        with h5py.File(path, "r") as h5file:
            position = h5file["particles/position"][()]
            v = h5file["particles/velocity"][()]
        if top is None:
            top = position[:, 1] > position[:, 1].max() - 1e-6
        times.append(time)
        velocity.append(float(np.mean(v[top, component])))
    return np.array(times), np.array(velocity)


def spectrum(v):
    """(f, V(f)) of a series sampled every SAMPLE seconds, zero-padded to PADDED seconds."""
    n = int(round(PADDED / SAMPLE))
    return np.fft.rfftfreq(n, SAMPLE), np.fft.rfft(v, n)


def crossing(f, phase, level):
    """The first frequency where the (falling) phase passes `level`, linearly interpolated."""
    below = np.nonzero(phase <= level)[0]
    if len(below) == 0 or below[0] == 0:
        return float("nan")
    k = below[0]
    return float(f[k - 1] + (level - phase[k - 1]) * (f[k] - f[k - 1]) / (phase[k] - phase[k - 1]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    common_arguments(parser, RESULTS,
                     output_help="parent of the output folders (default: outputs/, the runs "
                                 "overwrite outputs/site_response and outputs/site_response_s)",
                     no_run_help="analyse the existing outputs")
    args = parser.parse_args(argv)
    codes = [check_case(args, CASE, ""), check_case(args, CASE_S, "_s")]
    return max(codes)


def check_case(args, case_path, suffix):
    """Run and compare one column (P waves: suffix "", S waves: "_s"); the exit code."""
    case = load_json(case_path)
    waves = "S" if shear(case) else "P"
    output = (Path(args.output) if args.output else REPO / "outputs") / case["name"]
    wall = None
    try:
        if not args.no_run:
            if exe_missing(args.exe):
                return 2
            wall = run_mpm_geo(args.exe, case_path, output, overwrite=True,
                               quiet=args.quiet, cwd=REPO)
        t, v = top_velocity(output, 0 if shear(case) else 1)
        history = load_history(output)
    except (OSError, ValueError, KeyError, RuntimeError) as exc:
        print(f"check.py: error: {exc}", file=sys.stderr)
        return 2
    height, vp, alpha = column(case)
    grid = np.arange(0.0, t[-1] + 0.5 * SAMPLE, SAMPLE)
    f, top = spectrum(np.interp(grid, t, v))
    _, base = spectrum(outcrop(case, grid))
    transfer = top / base
    ratio = np.abs(transfer)
    kh = 2 * np.pi * f * height / vp
    closed = 1.0 / np.sqrt(np.cos(kh) ** 2 + alpha ** 2 * np.sin(kh) ** 2)
    band = (f > 0.5) & (f < 7.0)
    # the phase from 0.5 Hz on, unwrapped, started on the branch of the closed form's
    start = np.nonzero(band)[0][0]
    phase = np.unwrap(np.angle(transfer[start:]))
    closed_phase = -np.arctan2(alpha * np.sin(kh[start]), np.cos(kh[start]))
    phase += 2 * np.pi * np.round((closed_phase - phase[0]) / (2 * np.pi))
    results = []
    peaks = []
    for n in (1, 2, 3):
        fn = (2 * n - 1) * vp / (4 * height)
        fp = crossing(f[start:], phase, -(2 * n - 1) * np.pi / 2)
        amplification = float(np.interp(fn, f, ratio) * alpha)
        peaks.append((fn, fp, amplification / alpha))
        shift = float(fp / fn - 1.0)
        results.append(target(f"amplification x alpha - 1 at f_{n} = {fn:.3f} Hz",
                              amplification - 1.0, 0.0, f"+-{AMPLITUDE_BAND:.0%}",
                              abs(amplification - 1.0) <= AMPLITUDE_BAND, True,
                              "1 / alpha = 2 at every resonance of an undamped layer on "
                              "elastic rock (Kramer 1996, 7.2.1)", unit="%"))
        results.append(target(f"resonance {n} (phase -{2 * n - 1} pi / 2): frequency / f_{n}",
                              shift, 0.0,
                              f"+-{FREQUENCY_BAND:.0%}", abs(shift) <= FREQUENCY_BAND, True,
                              "where the phase of H passes -(2n - 1) pi / 2; f_n = (2n - 1) "
                              "vp / (4 H)", unit="%"))
    rms = float(np.sqrt(np.mean((ratio[band] - closed[band]) ** 2)) * alpha)
    results.append(target("RMS difference of the amplification, 0.5 to 7 Hz, x alpha", rms, 0.0,
                          "reported", True, False,
                          "the whole transfer function, not only its peaks", unit="%"))
    work = float(history["load_work"][-1])
    residual = float(history["residual"][-1])
    results.append(target("energy residual / work of the base", residual / work, 0.0,
                          "abs <= 2%", abs(residual / work) <= 0.02, True,
                          "what the base brought in (load_work) and took out "
                          "(boundary_work) close the balance", unit="%"))
    passed = all(r["passed"] for r in results if r["gating"])
    metrics = {
        "vp_m_s": vp, "height_m": height, "alpha": alpha,
        "resonances": [{"f_n_Hz": fn, "f_phase_Hz": fp, "amplification_at_f_n": a}
                       for fn, fp, a in peaks],
        "rms_over_peak": rms,
        "residual_over_work": residual / work,
        "kinetic_plus_elastic_at_end_over_work": float(
            (history["kinetic_energy"][-1] + history["elastic_energy"][-1]) / work),
    }

    figure = agg_figure(7.0, 4.6)
    axes = figure.add_subplot()
    axes.plot(f[band], closed[band], color="black", lw=1.2,
              label=f"closed form, alpha = {alpha:.2f}")
    axes.plot(f[band], ratio[band], color="tab:blue", lw=1.0, ls="--",
              label="mpm-geo: |top| / |outcrop|")
    for fn, fp, a in peaks:
        axes.plot(fn, a, "o", mfc="none", color="tab:red", ms=6)
        axes.axvline(fn, color="0.7", lw=0.7)
        axes.axvline(fp, color="tab:red", lw=0.7, ls=":")
    axes.set_xlabel("frequency [Hz]")
    axes.set_ylabel("amplification |H(f)|")
    axes.set_title(f"Site response of a 20 m elastic column on elastic rock ({waves} waves)",
                   fontsize=10)
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8)
    png = Path(args.results) / f"site_response{suffix}.png"
    png.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(png, dpi=110)

    worst = max(abs(p[2] * alpha - 1.0) for p in peaks)
    report = {
        "case": "site_response",
        "title": "1D site response on a compliant seismic base (transfer function)",
        "resolution": "full",
        "heading": f"H / dx = 40 (0.5 m cells), {waves} waves",
        "case_files": [relative(case_path)],
        "headline": f"The amplification at the first three resonances is "
                    f"{', '.join(f'{p[2]:.3f}' for p in peaks)} against 1 / alpha = "
                    f"{1 / alpha:.0f} (worst {worst:.1%}); the resonances (phase) at "
                    f"{', '.join(f'{p[1]:.3f}' for p in peaks)} Hz against "
                    f"{', '.join(f'{p[0]:.3f}' for p in peaks)} Hz; energy residual "
                    f"{residual / work:+.2%} of the base's work.",
        "setup": {"rows": [
            ["column", "20 m, 1 cell wide, " + ("periodic side faces (a laterally infinite "
                       "layer)" if shear(case) else "sliding walls") + ", free top; no "
                       "gravity, no damping"],
            ["soil", f"linear_elastic E 15 MPa, nu 0.3, rho 2000: "
                     f"{'vs' if shear(case) else 'vp'} = {vp:.2f} m/s"],
            ["base", "seismic, compliant: vp, vs of the rock twice the soil's (alpha = 0.5); "
                     f"outcrop velocity a 3.5 Hz Ricker wavelet, "
                     f"{'horizontal' if shear(case) else 'vertical'}"],
            ["grid", "dx = 0.5 m, 2 x 2 particles per cell, cpGIMP, MUSL, FLIP, 8 s"],
        ]},
        "metrics": metrics,
        "targets": results,
        "passed": passed,
        "wall_time_s": wall,
        "threads": os.environ.get("OMP_NUM_THREADS", str(os.cpu_count())),
        "plots": [png.name],
    }
    write_json(Path(args.results) / f"metrics{suffix}.json", report)
    for r in results:
        print(f"{r['name']:<52} {r['value']!s:<24} {r['band']:<10} {verdict(r)}")
    print(report["headline"])
    print(f"site_response ({waves} waves): {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
