"""benchmarks/splatting.py's start padded with jittered copies of its largest maps: the given maps first, each copy
within the jitter of one."""
import math

import torch

from common_testing import benchmark_module

padded_with_copies = benchmark_module("splatting").padded_with_copies

MAPS = torch.tensor([[[0.3, 0.0, -0.2], [0.0, 0.3, 0.1], [0, 0, 1]],
                     [[0.6, 0.0, 0.2], [0.0, 0.5, -0.1], [0, 0, 1]]], dtype=torch.float64)


def test_copies_of_the_largest_maps_in_turn_within_the_jitter():
    jitter = 0.03
    out = padded_with_copies(MAPS, 5, jitter, torch.Generator().manual_seed(0))
    assert out.shape == (5, 3, 3) and torch.equal(out[:2], MAPS)
    for copy, origin in zip(out[2:], MAPS[[1, 0, 1]]):  # the larger map (scale 0.6) first
        assert (copy[:2, 2] - origin[:2, 2]).abs().max() <= jitter
        # a rotation of the domain keeps the singular values and turns the linear part by at most jitter of a turn
        assert torch.allclose(torch.linalg.svdvals(copy[:2, :2]), torch.linalg.svdvals(origin[:2, :2]))
        assert 0 < (copy[:2, :2] - origin[:2, :2]).abs().max() <= 2 * math.pi * jitter * 0.6 * 1.01
        assert torch.equal(copy[2], origin[2])


def test_nothing_added_when_the_start_has_enough_maps():
    assert torch.equal(padded_with_copies(MAPS, 2, 0.03, torch.Generator()), MAPS)
