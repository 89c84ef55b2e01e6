"""`ifslib.automatic.fractal.moves`: turns keep the figure's moments, reorient and swap mend a wrong map."""
import numpy as np
import pytest

from ifslib.automatic import fractal
from ifslib.core.targets.target import foreground_points, resize_target
from common_testing import fractal_target


@pytest.mark.slow
def test_turns_keep_the_figure_mean_and_covariance_and_reorient_undoes_a_turned_map():
    truth, target = fractal_target(size=64)
    fg = foreground_points(target)
    for s in fractal.turns(target):
        moved = fg @ s[:, :2].T + s[:, 2]
        np.testing.assert_allclose(moved.mean(0), fg.mean(0), atol=1e-9)
        np.testing.assert_allclose(np.cov(moved.T), np.cov(fg.T), atol=1e-9)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    _, truth_error = fractal.refine(true_maps[None], target, 0, 0.0, 2000)
    turned = true_maps.copy()
    s = fractal.turns(target)[11]  # a half turn
    turned[1, :, :2] = true_maps[1, :, :2] @ s[:, :2]
    turned[1, :, 2] = true_maps[1, :, :2] @ s[:, 2] + true_maps[1, :, 2]
    _, turned_error = fractal.refine(turned[None], target, 0, 0.0, 2000)
    maps, error = fractal.reorient(turned, target)
    assert float(turned_error[0]) > 1.5 * float(truth_error[0])
    assert error <= 1.1 * float(truth_error[0])


@pytest.mark.slow
def test_swap_puts_back_a_map_that_the_sets_of_copies_left_out():
    truth, target = fractal_target(maps=3, seed=1, size=128)
    coarse = resize_target(target, 64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    wrong = true_maps.copy()
    wrong[2] = [[0.3, 0.0, -0.2], [0.0, 0.3, 0.2]]  # a small copy in the wrong place
    rng = np.random.default_rng(0)
    pool = np.concatenate([fractal.random_starts(60, 1, coarse, rng)[:, 0], true_maps[2:] + 0.004])
    best, before = fractal.attractor_iou(true_maps, target), fractal.attractor_iou(wrong, target)
    maps, after, kept = fractal.swap(wrong, pool, coarse, target, target, rounds=2)
    assert before < 0.2 and kept >= 1 and after >= best - 0.03  # as close as the true maps' attractor
    assert after == pytest.approx(fractal.attractor_iou(maps, target), abs=0.02)
    assert np.abs(maps - true_maps).max() < 0.02  # the true map, found in the pool, and the others kept
