"""`ifslib.core.raster.nearest`: the nearest-leaf search is exact, chunked and for tiny images."""
import pytest
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import sdf_dense
from ifslib.core.raster import nearest
from ifslib.core.raster.nearest import nearest_leaf, pixel_centres

from conftest import PATTERNS, perturbed, sheared, sheared_disks


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


def test_the_tangent_plane_bound_is_exact_and_prunes_more(pattern_name, monkeypatch):
    # on every kind (similar and sheared words, mixed kinds) and an image side that is not a power of two:
    # the brute force's distances; with the tangent planes (one kind of primitive) the winners of the
    # Lipschitz bound alone, from fewer distance evaluations
    ifs = perturbed(PATTERNS[pattern_name](), seed=3, dtype=torch.float32)
    leaves = expand(ifs, 3)
    size = 45
    x, y = pixel_centres(size, dtype=torch.float32)
    got = nearest_leaf(leaves, size)
    brute = sdf_dense(leaves, x, y).detach().min(dim=1).values
    assert (got.distance - brute).abs().max().item() <= 1e-6
    finer = nearest_leaf(leaves, 256)
    monkeypatch.setattr(nearest, "has_slope", lambda table, kind: False)  # the Lipschitz bound alone
    plain = nearest_leaf(leaves, size)
    assert torch.equal(got.leaf, plain.leaf) and torch.equal(got.distance, plain.distance)
    if pattern_name in ("affine_mixed", "mixed"):  # several kinds: no table, no slopes
        assert got.pairs == plain.pairs
    else:
        assert got.pairs < plain.pairs
    if pattern_name == "koch":  # segments of 8 px at 256²: many near-ties, and the plane drops most of them
        assert finer.pairs < 0.85 * nearest_leaf(leaves, 256).pairs


def _least_over_children(leaves, size, level, side):
    """``(4 ** (level + 1), leaves)``: each leaf's least distance over the pixel centres of each block of level + 1."""
    x, y = pixel_centres(size, dtype=leaves.inverse.dtype)
    dense = sdf_dense(leaves, x, y).detach().T.reshape(-1, 1, size, size)
    padded = torch.full((dense.shape[0], 1, side, side), float("inf"), dtype=dense.dtype)
    padded[..., :size, :size] = dense
    child = side >> (level + 1)
    return -torch.nn.functional.max_pool2d(-padded, child)[:, 0].flatten(1).T  # (blocks, leaves), row-major


BOUNDED = {"koch": lambda: ifslib.patterns.by_name("koch", depth=3),
           "carpet": lambda: ifslib.patterns.by_name("carpet", depth=3),
           "rosette6": lambda: ifslib.patterns.by_name("rosette6", depth=3),
           "sheared boxes": lambda: sheared("box", depth=3), "sheared segments": lambda: sheared("segment", depth=3),
           "sheared disks": lambda: sheared_disks(depth=3)}


@pytest.mark.parametrize("name", sorted(BOUNDED))
@pytest.mark.parametrize("seed", range(3))
def test_the_bound_never_exceeds_a_leaf_s_least_distance_over_a_child(name, seed):
    # the pruning test's lower bound, at every level, against each leaf's least distance over each child
    # block's pixels (the dense field); rosette6's thick segments put block centres on their spines, where
    # a float32 gradient's direction is noise and the plane alone would drop a winner

    ifs = perturbed(BOUNDED[name](), scale=0.02, seed=seed, dtype=torch.float32)
    leaves = expand(ifs, 3).detach()
    size = 96
    tree = nearest._quadtree(leaves, size)
    assert tree.slopes
    stack, checked = [nearest._first_task(tree)], 0
    while stack:
        task = stack.pop()
        d, slope, _, best = nearest._block_minimum(tree, task)
        if task.level == tree.top:
            continue
        lower = nearest._lower(tree, d, slope, task.level)
        least = _least_over_children(leaves, size, task.level, tree.side)
        child = (2 * task.rows[task.pair_block, None] + tree.quad_r) * (1 << task.level + 1) \
            + 2 * task.cols[task.pair_block, None] + tree.quad_c
        truth = least[child, task.pair_leaf[:, None]]
        assert (lower <= truth + 1e-7).all(), f"level {task.level}: the bound exceeds the distance"
        checked += lower.numel()
        stack += nearest._children(tree, task, d, slope, best, nearest.MAX_PAIRS)
    assert checked > 0
