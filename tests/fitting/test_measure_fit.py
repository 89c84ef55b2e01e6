"""Fitting a measure: probabilities recovered from an image of the measure, maps moved towards it, bad input."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib.fitting.measure_fit import MeasureFitOptions, check_measure_image, fit_measure, multiscale_loss
from ifslib.raster.measure import MeasureOptions, chaos_measure, measure_from_maps

QUICK = MeasureOptions(iterations=12, supersample=1, refine=1, max_lost=1.0)


def test_probabilities_recovered_from_a_chaos_game_histogram():
    """Maps given: the triangle's probabilities come back within 0.02 from a 32 px histogram (the fern: benchmark)."""
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    tri.probabilities = (0.5, 0.3, 0.2)
    target = chaos_measure(tri, 32, n=500_000)
    start = ifslib.patterns.sierpinski_triangle()
    fit = fit_measure(start, target, MeasureFitOptions(steps=30, lr=0.2, measure=QUICK))
    np.testing.assert_allclose(fit.probabilities, (0.5, 0.3, 0.2), atol=0.02)
    assert sum(fit.probabilities) == pytest.approx(1) and fit.ifs.probabilities == fit.probabilities
    assert fit.losses[-1] < fit.losses[0] / 5 and fit.correlation > 0.95  # 0.09 and 0.962 measured
    torch.testing.assert_close(fit.ifs.points, start.points)  # the maps were given: not moved


def test_fitting_the_maps_too_lowers_the_loss_and_keeps_fixed_points():
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    target = measure_from_maps(tri.maps().detach(), tri.measure_probabilities(), 32, QUICK)
    start = tri.jittered(0.01, np.random.default_rng(0))
    fit = fit_measure(start, target, MeasureFitOptions(steps=15, map_lr=0.002, fit_maps=True, measure=QUICK))
    assert fit.losses[-1] < 0.5 * fit.losses[0]
    moved = (fit.ifs.points.detach().double() - start.points.detach().double()).abs().sum(1)
    assert (moved[list(start.fixed)] == 0).all() and (moved[4:] > 0).all()


def test_the_loss_is_zero_only_for_equal_images_and_sees_coarse_shifts():
    a = torch.zeros(8, 8, dtype=torch.float64)
    a[2, 2] = 1
    b = torch.zeros_like(a)
    b[2, 3] = 1
    assert float(multiscale_loss(a, a, 3)) == 0
    assert float(multiscale_loss(a, b, 3)) < float(multiscale_loss(a, torch.roll(b, 4, 1), 3))


@pytest.mark.parametrize("call, message", [
    (lambda: check_measure_image(np.zeros((4, 4))), "some mass"),
    (lambda: check_measure_image(-np.ones((4, 4))), ">= 0"),
    (lambda: check_measure_image(np.ones((4, 5))), "square"),
    (lambda: MeasureFitOptions(steps=0), "steps"),
    (lambda: MeasureFitOptions(lr=float("nan")), "lr"),
    (lambda: MeasureFitOptions(fit_maps="yes"), "True or False"),
    (lambda: fit_measure(ifslib.patterns.koch(), np.ones((8, 8)), options={"steps": 3}), "MeasureFitOptions"),
])
def test_bad_input(call, message):
    with pytest.raises(ifslib.IFSError, match=message):
        call()
