"""Copies matched to uncovered regions (`ifslib.automatic.fractal.regions`) and the search's `region_swap`."""
import math

import numpy as np
import pytest

import ifslib
from ifslib.errors import IFSError
from ifslib.automatic import fractal
from ifslib.automatic.fractal import regions
from ifslib.core.targets.target import foreground_points, resize_target, target_from_mask


def _maps(ifs):
    return ifs.maps().detach()[:, :2, :].double().numpy()


def test_moment_maps_contain_the_map_that_made_the_region():
    """A region that is an affine copy of the figure is matched exactly by the rotation that made it."""
    rng = np.random.default_rng(0)
    figure = rng.normal(size=(500, 2)) @ np.array([[0.2, 0.05], [0.0, 0.1]]) + [0.05, -0.02]
    root = regions.sqrtm_psd(np.cov(figure.T))
    q = regions.rotation(2 * math.pi * 5 / 72) @ np.diag([1.0, -1.0])  # a reflection on the grid of 72 angles
    shrink = 0.35 * regions.rotation(0.3) @ np.diag([1.0, 0.5])  # the region's covariance: a copy's, shrink C shrink^T
    linear = regions.sqrtm_psd(shrink @ np.cov(figure.T) @ shrink.T) @ q @ np.linalg.inv(root)
    assert np.linalg.svd(linear)[1].max() < 0.9  # contracts: not clipped
    shift = np.array([0.1, 0.2])
    region = figure @ linear.T + shift
    maps = regions.moment_maps(figure, region, angles=72)
    assert maps.shape == (144, 2, 3)
    wanted = np.concatenate([linear, shift[:, None]], 1)
    assert np.abs(maps - wanted).max(axis=(1, 2)).min() < 1e-9
    # every map carries the figure's mean onto the region's and contracts
    assert np.allclose(maps[..., :2] @ figure.mean(0) + maps[..., 2], region.mean(0))
    assert np.linalg.svd(maps[..., :2])[1].max() <= 0.9 + 1e-12


def _drawn(maps, seed):
    """A random fractal (`random_ifs`) at 256² by the chaos game, and at 128²."""
    truth = ifslib.random_fractals.random_ifs(maps, seed)
    judge = target_from_mask(ifslib.render(truth, 256, method="chaos", points=400_000, seed=seed).numpy() >= 0.5)
    return _maps(truth), resize_target(judge, 128), judge


@pytest.fixture(scope="module")
def thin():
    """Benchmark fractal 30: four maps, two of them thin (0.42 x 0.09 and 0.39 x 0.11)."""
    return _drawn(4, 30)


def test_region_maps_give_back_a_map_whose_copy_stands_apart():
    """Benchmark fractal 27, map 0 (0.65 x 0.14): with the other maps true, the region they leave is nearly its copy,
    and the copies matched to it include the map to within 0.04 in every entry (a copy of the search's grid pool is
    0.14 or more from a thin map, docs/results/fractals.md)."""
    true, fine, judge = _drawn(5, 27)
    offers = regions.region_maps(true, 0, fine.mask, foreground_points(judge))
    assert 1 <= len(offers) <= fractal.DEFAULT.per_region * (1 + fractal.DEFAULT.parts)
    assert np.abs(offers - true[0]).max(axis=(1, 2)).min() < 0.04


def test_region_maps_reject_a_map_that_is_not_there(thin):
    true, fine, judge = thin
    with pytest.raises(IFSError, match="map 4"):
        regions.region_maps(true, 4, fine.mask, foreground_points(judge))


@pytest.mark.slow
def test_region_swap_replaces_a_wrong_thin_map(thin):
    """The thin map replaced by a round copy at its place: one round puts a thin one back and the IoU rises."""
    true, fine, judge = thin
    wrong = true.copy()
    wrong[0, :, :2] = 0.25 * np.eye(2)
    before = fractal.attractor_iou(wrong, judge)
    maps, after, kept = fractal.region_swap(wrong, fine, judge, foreground_points(judge))
    assert kept and after > before + 0.05
    assert after == pytest.approx(fractal.attractor_iou(maps, judge), abs=1e-9)


@pytest.mark.slow
def test_region_grow_adds_back_a_map_left_out(thin):
    """The maps but one: the copy they leave bare is matched, the map added back, and the attractor's IoU rises."""
    true, fine, judge = thin
    without = np.delete(true, 0, 0)
    before = fractal.attractor_iou(without, judge)
    grown, after = fractal.region_grow(without, fine, judge, foreground_points(judge))
    assert grown.shape == true.shape and after > before + 0.1
    assert after == pytest.approx(fractal.attractor_iou(grown, judge), abs=1e-9)
    # nothing is offered where the copies already cover the whole figure
    assert len(regions.uncovered_maps(np.array([[[1.0, 0, 0], [0, 1.0, 0]]]), fine.mask,
                                      foreground_points(judge))) == 0
