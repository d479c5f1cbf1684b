"""mpm_post.cantilever: the Sadeghirad beam shared by the study and the validation case (its
measures on a hand-made run, the Richardson error estimate and the bands derived from it)."""

import math

import numpy as np
import pytest

from mpm_post.cantilever import (
    PUBLISHED_PEAK, cantilever_case, measure, peak_bands, richardson)
from mpm_post_fakerun import write_output


def test_case_keys():
    case = cantilever_case(0.125, "bspline2", "MUSL", "flip", 3, tend=1.5)
    assert case["name"] == "cantilever_0p125_bspline2_MUSL_flip_3"
    assert case["time"]["tend"] == 1.5 and case["particles"]["ppc"] == 3
    assert (case["domain"]["nx"], case["domain"]["ny"]) == (36, 44)


def test_measure_reads_the_corner_particle_and_the_residual(tmp_path):
    start = np.zeros((3, 3))
    start[:, :2] = [[0.1, 4.9], [3.9, 4.1], [3.9, 4.9]]   # particle 1 nearest (4, 4)
    deflection = {0.0: 0.0, 0.5: 2.0, 1.0: 3.3, 1.5: 3.1}
    for index, (time, tip) in enumerate(deflection.items()):
        displacement = np.zeros((3, 3))
        displacement[:, 1] = -0.5 * tip
        displacement[1, 1] = -tip
        write_output(tmp_path / f"particles_{index:06d}.h5", time, index, 2,
                     {"position": start + displacement, "displacement": displacement})
    (tmp_path / "history.csv").write_text(
        "time,step,potential_energy,residual\n"
        "0.0,0,0.0,0.0\n0.5,1,-50.0,0.1\n1.0,2,-100.0,0.4\n1.5,3,-90.0,-0.8\n")
    m = measure(tmp_path)
    assert m["peak_m"] == pytest.approx(3.3) and m["peak_time_s"] == pytest.approx(1.0)
    assert m["residual_rel"] == pytest.approx(-0.008)        # -0.8 J over the 100 J drop
    assert m["residual_at_peak_rel"] == pytest.approx(0.004)
    assert m["particles"] == 3 and m["end_s"] == pytest.approx(1.5)


def test_richardson_recovers_a_second_order_ladder():
    values = [3.3 - 0.4 * h ** 2 for h in (0.25, 0.125, 0.0625)]
    fit = richardson(values)
    assert fit.monotone and fit.safety == 1.25
    assert fit.order == pytest.approx(2.0)
    assert fit.extrapolated == pytest.approx(3.3)
    assert fit.errors == pytest.approx([0.4 * h ** 2 for h in (0.25, 0.125, 0.0625)])
    assert fit.gci_fine == pytest.approx(1.25 * 0.4 * 0.0625 ** 2)


def test_richardson_without_an_order_is_wider():
    fit = richardson([3.30, 3.32, 3.31])            # oscillating: no observed order
    assert not fit.monotone and math.isnan(fit.order) and fit.safety == 3.0
    assert fit.extrapolated == 3.31 and fit.errors[-1] == pytest.approx(0.01)
    with pytest.raises(ValueError):
        richardson([3.3])


def test_bands_are_spread_plus_the_estimated_error():
    peaks = [3.2945, 3.3035, 3.3064]
    bands = peak_bands(peaks)
    fit = bands["richardson"]
    assert bands["spread_m"] == pytest.approx(0.01)
    for peak, band in zip(peaks, bands["peak_band_m"]):
        assert band == pytest.approx(0.01 + 1.25 * abs(peak - fit.extrapolated))
    assert bands["residual_band"] == pytest.approx(
        [b / PUBLISHED_PEAK for b in bands["peak_band_m"]])
    # the coarse rung carries the largest error and so the widest band
    assert bands["peak_band_m"][0] > bands["peak_band_m"][1] > bands["peak_band_m"][2]
