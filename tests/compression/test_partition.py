"""The quadtree: its leaves tile the image, the walk matches them, and the greedy growth keeps its budget."""
import numpy as np
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.partition import LevelCost, children, grow, leaves_in_order, top_nodes, walk

O = CodeOptions(min_block=4, max_block=16)


def covered(leaves, height, width):
    seen = np.zeros((height, width), int)
    for size, y, x in leaves:
        seen[y:y + size, x:x + size] += 1
    return seen


def test_leaves_tile_the_image_once():
    split = {(16, 0, 0), (8, 0, 8), (16, 16, 16)}
    leaves = leaves_in_order(32, 48, O, split)
    assert (covered(leaves, 32, 48) == 1).all()
    assert leaves[:4] == children((16, 0, 0))[:1] + children((8, 0, 8))[:3]


def test_walk_visits_nodes_depth_first_with_their_flags():
    split = {(16, 0, 0), (8, 8, 8)}
    visited = list(walk(16, 16, O, lambda node: node in split))
    assert [n for n, s in visited if not s] == leaves_in_order(16, 16, O, split)
    assert [n for n, s in visited if s] == [(16, 0, 0), (8, 8, 8)]


def costs(height, width, rng):
    """Random errors that shrink with the block size; bits that grow as blocks get smaller."""
    out = {}
    for size in O.sizes:
        grid = (height // size, width // size)
        out[size] = LevelCost(err=rng.random(grid) * size**3, bits=np.full(grid, 20 + 16 // size))
    return out


def test_growth_keeps_its_bit_budget_and_spends_it():
    rng = np.random.default_rng(0)
    c = costs(64, 64, rng)
    for budget in (400, 900, 3000):
        split = grow(64, 64, O, c, budget_bits=budget)
        leaves = leaves_in_order(64, 64, O, split)
        flags = sum(1 for node, _ in walk(64, 64, O, lambda n: n in split) if node[0] > O.min_block)
        bits = flags + sum(int(c[s].bits[y // s, x // s]) for s, y, x in leaves)
        assert bits <= budget
        assert (covered(leaves, 64, 64) == 1).all()
    assert len(grow(64, 64, O, c, budget_bits=3000)) > len(grow(64, 64, O, c, budget_bits=900))


def test_growth_stops_at_the_target_error():
    rng = np.random.default_rng(1)
    c = costs(32, 32, rng)
    everything = grow(32, 32, O, c)
    target = sum(float(c[16].err.sum()) for _ in [0]) / 2
    split = grow(32, 32, O, c, target_err=target)
    leaves = leaves_in_order(32, 32, O, split)
    err = sum(float(c[s].err[y // s, x // s]) for s, y, x in leaves)
    assert err <= target and len(split) < len(everything)
    assert top_nodes(32, 32, O) == [(16, 0, 0), (16, 0, 16), (16, 16, 0), (16, 16, 16)]
