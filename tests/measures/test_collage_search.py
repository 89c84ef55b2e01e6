"""The collage search: pushes correlated exactly, a lopsided triangle's maps and probabilities read from its gray
image alone, the same sets at 1 and 2 threads, bad input."""
import numpy as np
import pytest
import torch
from scipy import ndimage

import ifslib
from ifslib.errors import IFSError
from ifslib.measures.collage_search import (CollageSearchOptions, _Pushes, collage_search, fit_measure_from_collage,
                                            refine_collage)
from ifslib.measures.measure import MeasureOptions, chaos_measure
from ifslib.measures.measure_fit import MeasureFitOptions, pool_measure

#: The triangle at 32 px: the default blur, half a pixel there (one pixel smooths its half-size copies away), 12 turns.
SMALL = CollageSearchOptions(size=32, turns=12, refine_steps=200)
QUICK = MeasureOptions(iterations=12, supersample=1, refine=1, max_lost=1.0)


@pytest.fixture(scope="module")
def lopsided():
    tri = ifslib.patterns.sierpinski_triangle().to(torch.float64)
    tri.probabilities = (0.5, 0.3, 0.2)
    return tri, chaos_measure(tri, 64, n=1_000_000)


def brute_correlation(pushes, part, residual, r, c, blur, pad=64):
    """The image pushed by ``part`` with its centre of mass at pixel (r, c), splatted bilinearly on a wide canvas,
    blurred there, cut to the image and summed against ``residual``: no torus anywhere."""
    n = residual.shape[0]
    v = pushes.points.numpy() @ part.T
    col, row = c + v[:, 0] + pad, r - v[:, 1] + pad
    canvas = np.zeros((n + 2 * pad, n + 2 * pad))
    c0, r0 = np.floor(col).astype(int), np.floor(row).astype(int)
    fc, fr = col - c0, row - r0
    mass = pushes.mass.double().numpy()
    for dc, dr, w in ((0, 0, (1 - fc) * (1 - fr)), (1, 0, fc * (1 - fr)), (0, 1, (1 - fc) * fr), (1, 1, fc * fr)):
        np.add.at(canvas, (r0 + dr, c0 + dc), w * mass)
    blurred = ndimage.gaussian_filter(canvas, blur, mode="constant")
    return (blurred[pad:pad + n, pad:pad + n] * residual).sum(), np.linalg.norm(blurred)


def test_the_fft_correlation_and_norm_are_the_brute_force_ones():
    """Each push's correlation with a residual at every translation (by FFT, on the padded torus) is the sum over the
    image's pixels of the blurred push placed there on an unbounded canvas: no push wraps round onto the image."""
    rng = np.random.default_rng(0)
    image = torch.zeros(24, 24, dtype=torch.float64)
    image[4:20, 6:18] = torch.as_tensor(rng.random((16, 12)))
    pushes = _Pushes(image / image.sum(), CollageSearchOptions(size=24, turns=4, blur=1 / 24))
    residual = rng.random((24, 24))
    side, n = pushes.side, 24
    spectrum = torch.fft.rfft2(torch.nn.functional.pad(torch.as_tensor(residual), (0, side - n, 0, side - n)))
    for index in (0, len(pushes.grid) // 2, len(pushes.grid) - 1):   # the largest copies last
        pushed = torch.fft.rfft2(pushes._canvases(pushes.grid[index:index + 1]).double()) * pushes.kernel.to(torch.complex128)
        fast = torch.fft.irfft2(torch.conj(pushed) * spectrum, s=(side, side))[0, :n, :n].numpy()
        norm = float(((pushed.real ** 2 + pushed.imag ** 2) * pushes.weight.double()).sum().sqrt())
        for r, c in ((0, 0), (5, 17), (23, 23), (12, 3)):
            slow, slow_norm = brute_correlation(pushes, pushes.grid[index], residual, r, c, 1.0)
            np.testing.assert_allclose(fast[r, c], slow, rtol=1e-4)
            np.testing.assert_allclose(norm, slow_norm, rtol=1e-3)


@pytest.mark.slow
def test_a_lopsided_triangle_s_maps_and_probabilities_come_from_its_gray_image(lopsided):
    """The support cannot tell (0.5, 0.3, 0.2) from any other probabilities; its collage can (measured: 0.491, 0.297,
    0.211, every map's larger singular value 0.50, the smaller 0.44 to 0.50)."""
    _, image = lopsided
    found = collage_search(image, 3, SMALL)
    assert len(found) == SMALL.beams and [f.collage for f in found] == sorted(f.collage for f in found)
    best = found[0]
    np.testing.assert_allclose(sorted(best.ifs.probabilities, reverse=True), (0.5, 0.3, 0.2), atol=0.03)
    scales = np.linalg.svd(best.ifs.maps().detach().numpy()[:, :2, :2])[1]
    np.testing.assert_allclose(scales[:, 0], 0.5, atol=0.03)   # the fit after the search settles the rest
    np.testing.assert_allclose(scales[:, 1], 0.5, atol=0.08)
    assert 0 < best.residual < 1


@pytest.mark.slow
def test_the_fit_from_the_collage_reaches_the_measure(lopsided):
    _, image = lopsided
    fit = fit_measure_from_collage(image, 3, MeasureFitOptions(steps=30, map_lr=0.001, fit_maps=True, measure=QUICK),
                                   SMALL)
    assert fit.correlation > 0.95 and fit.start is not None
    assert sum(fit.probabilities) == pytest.approx(1)


def test_refining_lowers_the_collage_error_and_keeps_maps_contracting(lopsided):
    tri, image = lopsided
    small = pool_measure(image, 32).double()
    maps = tri.maps().detach().double().clone()
    maps[:, :2, :2] *= 1.15   # too large: the collage of a wrong set
    maps[0, :2, 2] += 0.03
    _, _, before = refine_collage(small, maps, np.array([0.4, 0.3, 0.3]), 0, 0.002)
    refined, p, after = refine_collage(small, maps, np.array([0.4, 0.3, 0.3]), 150, 0.002)
    assert after < 0.5 * before
    assert torch.linalg.svdvals(refined[:, :2, :2]).max() <= 0.95 + 1e-9
    assert float(p.sum()) == pytest.approx(1)


def test_the_blur_is_a_share_of_the_frame():
    assert CollageSearchOptions().blur_pixels == 1.0 and CollageSearchOptions(size=32).blur_pixels == 0.5


@pytest.mark.slow
def test_the_same_sets_at_one_and_two_threads(lopsided):
    _, image = lopsided
    options = CollageSearchOptions(size=32, turns=6, refine_steps=20, beams=2)
    before = torch.get_num_threads()
    try:
        runs = []
        for threads in (1, 2):
            torch.set_num_threads(threads)
            runs.append(collage_search(image, 3, options))
    finally:
        torch.set_num_threads(before)
    for one, two in zip(*runs):
        torch.testing.assert_close(one.ifs.maps(), two.ifs.maps(), rtol=1e-6, atol=1e-9)
        assert one.residual == pytest.approx(two.residual, rel=1e-9)


@pytest.mark.parametrize("call, message", [
    (lambda img: collage_search(img, 0), "maps"),
    (lambda img: collage_search(img, 3, "fast"), "CollageSearchOptions"),
    (lambda img: collage_search(img, 3, CollageSearchOptions(size=48)), "divide"),
    (lambda img: collage_search(-img, 3), ">= 0"),
    (lambda img: fit_measure_from_collage(img, 3, options="slow"), "MeasureFitOptions"),
    (lambda img: CollageSearchOptions(blur=0), "blur"),
    (lambda img: CollageSearchOptions(blur=1.0), "share of the frame"),
    (lambda img: CollageSearchOptions(turns=0), "turns"),
    (lambda img: CollageSearchOptions(progress="yes"), "progress"),
])
def test_bad_input(call, message):
    image = np.ones((64, 64)) / 64 ** 2
    with pytest.raises(IFSError, match=message):
        call(image)
