"""Fitting a measure: probabilities recovered from an image of the measure, maps moved towards it, bad input."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib.automatic.plan import Plan
from ifslib.measures import measure_fit
from ifslib.measures.measure_fit import (MAX_FIT_SCALE, MeasureFitOptions, check_measure_image, fit_measure,
                                        fit_measure_from_support, multiscale_loss, pool_measure, reorient,
                                        support_symmetries, support_target)
from ifslib.core.geometry.rules import singular_values
from ifslib.measures.measure import MeasureOptions, chaos_measure, measure_from_maps

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


def test_halve_step_halves_until_the_maps_contract_else_undoes_the_step():
    points, before = torch.tensor([1.0]), torch.tensor([0.0])
    measure_fit.halve_step(points, before, lambda: float(points) < 0.3, 8)
    assert float(points) == 0.25
    measure_fit.halve_step(points, before, lambda: False, 3)
    assert float(points) == 0.0


def test_a_step_that_would_stop_a_map_contracting_is_shortened():
    """From maps of scale 0.95 with a step far too large, every map stays below `MAX_FIT_SCALE` after each step."""
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    target = measure_from_maps(tri.maps().detach(), tri.measure_probabilities(), 16, QUICK)
    wide = ifslib.patterns.affine([[[0.95, 0, 0], [0, 0.3, 0]], [[0.3, 0, 0.1], [0, 0.3, 0.1]]]).to(torch.float64)
    seen = []
    original = measure_fit.halve_step

    def watched(points, before, contracts, times):
        original(points, before, contracts, times)
        seen.append(float(singular_values(wide.clone(points.detach()).maps().detach())[1].max()))

    measure_fit.halve_step = watched
    try:
        fit_measure(wide, target, MeasureFitOptions(steps=4, map_lr=0.05, fit_maps=True, measure=QUICK))
    finally:
        measure_fit.halve_step = original
    assert len(seen) == 4 and max(seen) < MAX_FIT_SCALE


def test_the_support_is_the_pixels_with_mass_and_pooling_keeps_mass():
    image = np.random.default_rng(0).random((8, 8)) * (np.random.default_rng(1).random((8, 8)) > 0.5)
    np.testing.assert_array_equal(support_target(image).mask, image > 0)
    np.testing.assert_array_equal(support_target(image, 0.5).mask, image > 0.5 * image.max())
    pooled = pool_measure(image, 4).numpy()
    np.testing.assert_allclose(pooled[1, 2], image[2:4, 4:6].sum() / image.sum())
    assert pooled.sum() == pytest.approx(1)


def test_the_support_s_maps_start_the_measure_fit(monkeypatch):
    """The search (44 s at 128 px on the fern: the benchmark) replaced by a plan of jittered triangle maps:
    those maps start the fit, which is read at fit_size and moves towards the gray levels."""
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    tri.probabilities = (0.5, 0.3, 0.2)
    image = chaos_measure(tri, 128, n=100_000)
    found = ifslib.patterns.sierpinski_triangle().jittered(0.01, np.random.default_rng(0))
    asked = []

    def search(target, maps=None, seed=0):
        asked.append((target.size, int(target.mask.sum()), maps))
        return Plan(found, (found,), "fractal", {})

    monkeypatch.setattr(measure_fit, "discover", search)
    fit = fit_measure_from_support(image, 3, MeasureFitOptions(steps=12, lr=0.2, map_lr=0.002, fit_maps=True,
                                                                 measure=QUICK), fit_size=32, turn=False)
    assert asked == [(128, int((image > 0).sum()), 3)] and fit.start is found
    assert fit.losses[-1] < fit.losses[0] / 2 and fit.correlation > 0.9
    monkeypatch.setattr(measure_fit, "discover", lambda *a, **k: Plan(found, (found,), "shape", {}))
    with pytest.raises(ifslib.IFSError, match="no fractal's maps"):
        fit_measure_from_support(image, fit_size=32)


def test_the_triangle_s_symmetries_are_found_and_turned_copies_turned_back():
    """The triangle's support has its six symmetries; copies turned by a third of a turn draw the same set but not the
    lopsided measure, and `reorient` turns each back (the loss falls to the true maps' level)."""
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    tri.probabilities = (0.6, 0.25, 0.15)
    sym = support_symmetries(support_target(chaos_measure(tri, 32, n=50_000)))
    assert len(sym) == 6 and np.allclose(sym[0], np.eye(3))
    line = np.zeros((16, 16))
    line[8, 2:14] = 1
    assert np.array_equal(support_symmetries(support_target(line)), np.eye(3)[None])  # no round frame: identity alone
    maps = tri.maps().detach()
    third = next(torch.as_tensor(s) for s in sym  # a third of a turn: trace -1, a rotation
                 if abs(np.trace(s[:2, :2]) + 1) < 0.05 and np.linalg.det(s[:2, :2]) > 0)
    turned = ifslib.patterns.affine(maps @ third, dtype=torch.float64)
    image = measure_from_maps(maps, tri.probabilities, 16, QUICK)
    options = MeasureFitOptions(lr=0.2, measure=QUICK, scales=3)
    back = reorient(turned, image, sym, options, steps=8)

    def loss(ifs):
        return float(multiscale_loss(measure_from_maps(ifs.maps().detach().double(), ifs.measure_probabilities(), 16,
                                                       QUICK), image, 3))
    turned.probabilities = back.probabilities
    assert loss(back) < 0.2 * loss(turned)
    torch.testing.assert_close(back.maps().detach().double(), maps, atol=1e-6, rtol=0)


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
    (lambda: support_target(np.ones((4, 4)), 1.0), "threshold"),
    (lambda: support_target(np.ones((4, 4))), "fills the frame"),
    (lambda: pool_measure(np.ones((6, 6)), 4), "must divide"),
    (lambda: fit_measure_from_support(np.ones((64, 64)), fit_size=32), "128 px"),
    (lambda: MeasureFitOptions(lr=float("nan")), "lr"),
    (lambda: MeasureFitOptions(fit_maps="yes"), "True or False"),
    (lambda: fit_measure(ifslib.patterns.koch(), np.ones((8, 8)), options={"steps": 3}), "MeasureFitOptions"),
])
def test_bad_input(call, message):
    with pytest.raises(ifslib.IFSError, match=message):
        call()
