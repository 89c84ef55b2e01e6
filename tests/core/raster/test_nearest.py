"""`ifslib.core.raster.nearest`: the nearest-leaf search is exact, chunked, for tiny images and warm-started along a fit."""
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import sdf_dense, sdf_pairs
from ifslib.core.raster.nearest import nearest_leaf, pixel_centres

from conftest import PATTERNS, perturbed


def test_search_is_exact_when_chunked_and_for_tiny_images():
    ifs = perturbed(ifslib.patterns.koch(), seed=7)
    leaves = expand(ifs, 3)
    x, y = pixel_centres(24)
    want = sdf_dense(leaves, x, y).detach().min(dim=1)
    for max_pairs in (1 << 22, 50):
        got = nearest_leaf(leaves, 24, max_pairs=max_pairs)
        torch.testing.assert_close(got.distance, want.values, rtol=0, atol=0)
    one = nearest_leaf(leaves, 1)
    assert one.leaf.shape == (1,)


def test_warm_started_search_equals_brute_force_along_a_whole_fit(pattern_name):
    # each step's search is capped by the distance to the previous step's winners (the warm start);
    # along 25 Adam steps it must give the brute force's distances and the cold search's winners
    ifs = perturbed(PATTERNS[pattern_name](), seed=11, dtype=torch.float32)
    size, depth = 29, 2
    x, y = pixel_centres(size, dtype=torch.float32)
    opt = torch.optim.Adam([ifs.points], lr=0.01)
    fixed = list(ifs.fixed)
    previous, changed = None, 0
    for _ in range(25):
        opt.zero_grad()
        leaves = expand(ifs, depth)
        cold = nearest_leaf(leaves, size)
        if previous is not None:
            upper = sdf_pairs(leaves.detach(), x, y, previous)
            warm = nearest_leaf(leaves, size, upper=upper)
            brute = sdf_dense(leaves, x, y).detach().min(dim=1).values
            assert torch.equal(warm.leaf, cold.leaf)
            assert (warm.distance - brute).abs().max().item() <= 1e-6
            assert warm.pairs <= cold.pairs
            changed += (cold.leaf != previous).sum().item()
        previous = cold.leaf
        field = sdf_pairs(leaves, x, y, cold.leaf)
        (field - 0.05).square().mean().backward()
        if fixed:
            ifs.points.grad[fixed] = 0
        opt.step()
    assert changed > 0  # the winners did move: the warm start was put to the test
