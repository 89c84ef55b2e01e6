"""Rendering: range, the sigma default, and the pixel grid of docs/guide/conventions.md."""
import math

import pytest
import torch

import ifslib


def test_pixel_grid_orientation():
    """A disk in the upper-right quadrant lights rows at the top and columns at the right."""
    pts = [[0.25, 0.25], [-0.5, -0.5], [0.5, 0.5], [-0.1, -0.1], [0.1, 0.1]]
    ifs = ifslib.IFS(pts, [{"kind": "square", "from": [1, 2], "to": [3, 4]}], [{"kind": "disk", "points": [0], "radius": 0.05}],
                     depth=0)
    img = ifslib.render(ifs, 20).detach()
    r, c = divmod(int(img.argmax()), 20)
    assert (r, c) in {(4, 14), (4, 15), (5, 14), (5, 15)}  # pixel (r, c): x = -0.5 + (c + .5)/20, y = 0.5 - (r + .5)/20
    d = ifslib.distance_field(ifs, 20).detach()
    x = -0.5 + (15 + 0.5) / 20
    y = 0.5 - (4 + 0.5) / 20
    assert d[4, 15].item() == pytest.approx(math.hypot(x - 0.25, y - 0.25) - 0.05, abs=1e-6)


def test_render_range_default_sigma_and_override():
    ifs = ifslib.patterns.koch(depth=2)
    img = ifslib.render(ifs, 32).detach()
    assert img.shape == (32, 32) and 0 <= img.min() and img.max() <= 1
    d = ifslib.distance_field(ifs, 32).detach()
    torch.testing.assert_close(img, torch.exp(-torch.relu(d) ** 2 * 32 ** 2))  # sigma = one pixel
    wide = ifslib.render(ifs, 32, sigma=4 / 32).detach()
    assert wide.sum() > img.sum()
    ifs.sigma = 4 / 32
    torch.testing.assert_close(ifslib.render(ifs, 32).detach(), wide)
    with pytest.raises(ValueError, match="sigma must be a finite number > 0"):
        ifslib.render(ifs, 32, sigma=0)


def test_inside_boxes_render_as_one():
    img = ifslib.render(ifslib.patterns.grid(2, depth=1), 16).detach()
    assert img[8, 8] == 1.0 and img[0, 0] < 0.5  # the plane's centre is inside, the corner outside


def test_the_chaos_games_mask_is_the_pixels_its_drawing_shades_at_least_half():
    # figure_mask of the chaos game splats each point on the pixel centres within reach (no KD-tree): the same
    # pixels as thresholding the drawing, whose shade is of the distance to the nearest point
    import numpy as np
    from common_testing import benchmark_module
    literature_ifs = benchmark_module("samplers").literature_ifs
    from ifslib.core.raster.chaos import chaos_field, chaos_reach
    from ifslib.core.raster.render import figure_mask

    for ifs in (ifslib.random_fractals.random_ifs(3, 1), literature_ifs("stem", 3, 0), ifslib.patterns.fern()):
        for size, points, sigma in ((64, 20_000, None), (97, 20_000, 0.03), (128, 5_000, 0.002)):
            fast = figure_mask(ifs, size, "attractor", sigma, method="chaos", points=points, seed=2)
            with torch.no_grad():
                drawn = ifslib.render(ifs, size, "attractor", sigma, method="chaos", points=points, seed=2)
            assert np.array_equal(fast, drawn.numpy() >= 0.5)
    # where the nearest point is within reach, a pixel's least pair distance is the drawing's distance, exactly
    ifs = ifslib.random_fractals.random_ifs(2, 4)
    pixel, distance = chaos_reach(ifs, 50, 0.05, 3_000, seed=1)
    field = chaos_field(ifs, 50, 3_000, seed=1).numpy().ravel()
    least = np.full(50 * 50, np.inf)
    np.minimum.at(least, pixel, distance)
    assert np.array_equal(least <= 0.05, field <= 0.05) and np.array_equal(least[field <= 0.05], field[field <= 0.05])
    with pytest.raises(ifslib.IFSError, match="radius"):
        chaos_reach(ifs, 50, -1.0)
