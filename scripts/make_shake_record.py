#!/usr/bin/env python3
"""Write data/shake_2hz_0p25g.csv, the base velocity record of inputs/seismic_slope.json.

A sine of 2 Hz whose peak acceleration is 0.25 g (velocity amplitude 0.25 g / (2 pi f) =
0.195 m/s), tapered in and out by half-cosines of 0.75 s, 4 s long, rows every 0.005 s: the
velocity starts and ends at zero, so the base comes back to rest (its net displacement, the
integral of the tapered sine, is below a millimetre).

    python3 scripts/make_shake_record.py [output.csv]
"""
import math
import sys

FREQUENCY = 2.0        # [Hz]
PEAK_ACCELERATION = 0.25 * 9.81  # [m/s2]
DURATION = 4.0         # [s]
TAPER = 0.75           # [s]
STEP = 0.005           # [s]


def taper(t):
    """Half-cosine ramps at both ends, 1 between."""
    if t < TAPER:
        return 0.5 * (1.0 - math.cos(math.pi * t / TAPER))
    if t > DURATION - TAPER:
        return 0.5 * (1.0 - math.cos(math.pi * (DURATION - t) / TAPER))
    return 1.0


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "data/shake_2hz_0p25g.csv"
    amplitude = PEAK_ACCELERATION / (2.0 * math.pi * FREQUENCY)
    rows = ["time,velocity"]
    for i in range(int(round(DURATION / STEP)) + 1):
        t = i * STEP
        rows.append(f"{t:.3f},{amplitude * taper(t) * math.sin(2.0 * math.pi * FREQUENCY * t):.6e}")
    with open(out, "w", encoding="utf-8") as handle:
        handle.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
