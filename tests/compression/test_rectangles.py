"""Rectangular blocks: the 4 isometries against brute force, the pool by hand, and the HV split's edge."""
import itertools

import pytest
import torch

from ifslib.compression.domains import domain_step, isometry, pool
from ifslib.compression.rectangles import (Block, edge_split, isometry_count, rectangle_isometry,
                                           rectangle_pool, rectangle_step, split_block)
from ifslib.errors import IFSError
from compression_images import photo


def _shape_keeping_permutations(h, w):
    """Every isometry of the h x w grid by brute force: maps of the corners' coordinates that keep all
    pixel distances, applied as index permutations."""
    out = set()
    coords = [(r, c) for r in range(h) for c in range(w)]
    for flip_r, flip_c, swap in itertools.product((0, 1), repeat=3):
        def move(r, c):
            r, c = (h - 1 - r if flip_r else r), (w - 1 - c if flip_c else c)
            return (c, r) if swap else (r, c)
        moved = [move(r, c) for r, c in coords]
        if all(0 <= r < h and 0 <= c < w for r, c in moved):
            out.add(tuple(moved))
    return out


@pytest.mark.parametrize("h, w", [(4, 8), (6, 2), (4, 4)])
def test_isometries_are_the_grids_symmetries_found_by_brute_force(h, w):
    block = torch.arange(float(h * w)).reshape(h, w)
    by_hand = set()
    for perm in _shape_keeping_permutations(h, w):
        image = torch.empty(h, w)
        for (r, c), value in zip(perm, block.reshape(-1).tolist()):
            image[r, c] = value
        by_hand.add(tuple(image.reshape(-1).tolist()))
    ours = {tuple(rectangle_isometry(block, k).reshape(-1).tolist()) for k in range(isometry_count(h, w))}
    assert ours == by_hand
    assert len(ours) == (8 if h == w else 4)


def test_square_blocks_keep_the_quadtrees_isometries_and_rectangles_refuse_a_fifth():
    block = photo(8)
    for k in range(8):
        assert torch.equal(rectangle_isometry(block, k), isometry(block, k))
    assert torch.equal(rectangle_isometry(block[:4], 3), torch.rot90(block[:4], 2))
    with pytest.raises(IFSError, match="does not apply"):
        rectangle_isometry(block[:4], 4)


@pytest.mark.parametrize("bh, bw", [(4, 8), (3, 5), (8, 4), (4, 4)])
def test_rectangle_pool_is_each_lattice_block_averaged_by_hand(bh, bw):
    image = photo(32)
    sy, sx = rectangle_step(32, 32, bh, bw)
    blocks = rectangle_pool(image, bh, bw)
    cols = (32 - 2 * bw) // sx + 1
    assert blocks.shape[1:] == (bh, bw) and len(blocks) % cols == 0
    for d in (0, cols - 1, len(blocks) - 1):
        y, x = (d // cols) * sy, (d % cols) * sx
        by_hand = image[y:y + 2 * bh, x:x + 2 * bw].reshape(bh, 2, bw, 2).mean((1, 3))
        torch.testing.assert_close(blocks[d], by_hand)
    with pytest.raises(IFSError, match="no domain"):
        rectangle_pool(image, 17, 4)


def test_a_square_blocks_pool_is_the_quadtrees():
    image = photo(64)
    for size in (4, 8, 16):
        assert rectangle_step(256, 256, size, size) == (domain_step(256, 256, size),) * 2
        torch.testing.assert_close(rectangle_pool(image, size, size), pool(image, size))


def test_edge_split_finds_a_step_edge_and_keeps_parts_at_least_min_side():
    block = torch.zeros(16, 16)
    block[:, 10:] = 1  # a vertical edge between columns 9 and 10
    assert edge_split(block, 4) == (1, 10)
    assert edge_split(block.T, 4) == (0, 10)
    block[:, 14:] = 0.5  # the stronger jump now lies too close to the side: only cuts 4-12 are allowed
    axis, position = edge_split(block, 4)
    assert axis == 1 and 4 <= position <= 12
    assert edge_split(torch.rand(7, 7), 4) is None


