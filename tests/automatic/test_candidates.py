"""`ifslib.automatic.fractal.candidates`: the grid of linear parts, the copies that fit inside the figure
(against brute force), and their maps in plane units."""
from dataclasses import replace

import numpy as np

from ifslib.automatic import fractal
from ifslib.automatic.fractal import candidates
from ifslib.core.targets.target import foreground_points
from common_testing import fractal_target


def test_the_linear_grid_is_its_formula_in_order_entry_by_entry():
    turns, phases, scales, ratios = 5, 3, (0.3, 0.7), (0.5, 1.0)
    expected = [fractal.rotation(theta) @ np.diag([s, sign * r * s]) @ fractal.rotation(phi)
                for s in scales for r in ratios for phi in ([0.0] if r == 1.0 else np.arange(phases) * np.pi / phases)
                for theta in np.arange(turns) * 2 * np.pi / turns for sign in (1.0, -1.0)]
    grid = fractal.linear_grid(turns=turns, phases=phases, scales=scales, ratios=ratios)
    assert grid.shape == (len(expected), 2, 2) == (2 * (3 + 1) * 5 * 2, 2, 2)
    np.testing.assert_array_equal(grid, np.array(expected))
    s = np.linalg.svd(grid, compute_uv=False)
    assert np.allclose(s[:, 0], np.repeat(scales, len(grid) // 2))  # the larger singular value is the scale


def test_copy_candidates_count_the_copy_pixels_on_the_grown_figure_as_brute_force_does():
    from scipy import ndimage

    _, target = fractal_target(size=32)
    grid = fractal.linear_grid(turns=4, phases=2, scales=(0.45, 0.75), ratios=(0.5, 1.0))
    cands = fractal.copy_candidates(target.mask, grid, per_map=3, config=replace(fractal.DEFAULT, inside=0.0))
    grown = ndimage.binary_dilation(target.mask)
    pts = candidates.pixels(target.mask)
    u = pts - pts.mean(0)
    assert len(cands) > 0
    for hits, g, row, col in cands[:40]:
        v = np.round(u @ grid[g].T).astype(int)
        drawn = {(row - y, col + x) for x, y in v}  # pixel (x, y) = (col, -row)
        on = sum(0 <= r < 32 and 0 <= c < 32 and grown[r, c] for r, c in drawn)
        assert on == hits


def test_copy_candidates_count_every_placement_as_brute_force_does_even_for_a_figure_in_a_corner():
    # every placement of every copy (per_map: all of them) counted by hand and ranked by the same exact key: the
    # FFT's padding, sized to the copies' reach, must never wrap a copy's pixels back onto the figure
    from scipy import ndimage

    _, target = fractal_target(size=24)
    mask = np.zeros((24, 24), bool)
    mask[:18, 6:] = target.mask[3:21, :18]  # pushed to the top right: copies reach past the frame
    grid = fractal.linear_grid(turns=6, phases=2, scales=(0.35, 0.85), ratios=(0.4, 1.0))
    config = replace(fractal.DEFAULT, inside=0.6)
    cands = fractal.copy_candidates(mask, grid, per_map=576, chunk=7, config=config)
    padded = np.pad(ndimage.binary_dilation(mask), 24)
    u = candidates.pixels(mask) - candidates.pixels(mask).mean(0)
    expected = []
    for g, linear in enumerate(grid):
        drawn = {(-y, x) for x, y in np.round(u @ linear.T).astype(int)}  # offsets (row, col) from the centroid
        hits = sum(padded[24 + dr:48 + dr, 24 + dc:48 + dc].astype(int) for dr, dc in drawn).ravel()
        key = np.where(hits >= config.inside * len(drawn) - 0.5, hits, 0) * 576 + (575 - np.arange(576))
        value = np.sort(key)[::-1]
        count, index = value // 576, 575 - value % 576
        expected += [(k, g, i // 24, i % 24) for k, i in zip(count, index) if k >= 1]
    expected = np.array(expected)
    np.testing.assert_array_equal(cands, expected[np.argsort(-expected[:, 0], kind="stable")])


def test_plane_maps_send_the_figure_centroid_to_the_candidate_pixel():
    _, target = fractal_target(size=32)
    grid = fractal.linear_grid(turns=4, phases=2, scales=(0.5,), ratios=(0.5, 1.0))
    cands = fractal.copy_candidates(target.mask, grid, config=replace(fractal.DEFAULT, inside=0.0))[:10]
    centroid = candidates.pixels(target.mask).mean(0)
    maps = fractal.plane_maps(grid, cands, centroid, 32)
    mu = foreground_points(target).mean(0)  # the same centroid, in plane units
    for m, (_, g, row, col) in zip(maps, cands):
        np.testing.assert_allclose(m[:, :2], grid[g])
        np.testing.assert_allclose(m[:, :2] @ mu + m[:, 2], [(col + 0.5) / 32 - 0.5, 0.5 - (row + 0.5) / 32], atol=1e-12)
