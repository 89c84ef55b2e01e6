"""Lever 3 of issue 13, measured: does warm-starting the nearest-leaf search pay?

Along a Koch fit (Adam on the multiscale pixel loss, from the best-fit line), each step runs the
search twice: cold (`ifslib.nearest_leaf` as fits use it) and warm (``upper`` = each pixel's distance to
its winner of the previous step, which caps every block's bound by the largest of its pixels').
Both must give the same winners (checked at every step). Printed: (block, leaf) pairs evaluated
and the median time of each, per configuration.

Run ``python benchmarks/warm_search.py [--steps N]``. Times are wall-clock medians with torch's
current thread count (set ``IFSLIB_THREADS``); on a shared machine they are noisy, the pair
counts are not.
"""
from __future__ import annotations

import argparse
import statistics
import time

import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import sdf_pairs

CONFIGS = [(64, 3), (256, 3), (512, 5)]


def measure(size: int, depth: int, steps: int) -> dict:
    """Cold and warm searches along ``steps`` Adam steps of a Koch fit at ``size``/``depth``."""
    target = ifslib.load_target(ifslib.patterns.koch(depth=depth), size)
    ifs = ifslib.initialize(ifslib.patterns.koch(depth=depth), target)
    x, y = ifslib.pixel_centres(size, "cpu", ifs.points.dtype)
    opt = torch.optim.Adam([ifs.points], lr=0.003)
    previous = None
    out = {"cold_pairs": 0, "warm_pairs": 0, "cold_s": [], "warm_s": []}
    for _ in range(steps):
        opt.zero_grad()
        leaves = expand(ifs, depth)
        t0 = time.perf_counter()
        cold = ifslib.nearest_leaf(leaves, size)
        t1 = time.perf_counter()
        if previous is not None:
            upper = sdf_pairs(leaves.detach(), x, y, previous)
            warm = ifslib.nearest_leaf(leaves, size, upper=upper)
            t2 = time.perf_counter()
            if not torch.equal(warm.leaf, cold.leaf):
                raise AssertionError(f"warm and cold searches differ at {size}²/depth {depth}")
            out["cold_pairs"] += cold.pairs
            out["warm_pairs"] += warm.pairs
            out["cold_s"].append(t1 - t0)
            out["warm_s"].append(t2 - t1)
        previous = cold.leaf
        field = sdf_pairs(leaves, x, y, cold.leaf).view(size, size)
        ifslib.loss(field, target, "multiscale_pixel").backward()
        opt.step()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=30, help="fit steps per configuration")
    args = parser.parse_args()
    print(f"cold vs warm nearest-leaf search along {args.steps} Koch fit steps, {torch.get_num_threads()} threads")
    print(f"{'size':>5} {'depth':>5} {'cold pairs/step':>16} {'warm pairs/step':>16} {'saved':>6} "
          f"{'cold ms':>8} {'warm ms':>8}")
    for size, depth in CONFIGS:
        r = measure(size, depth, args.steps)
        n = len(r["cold_s"])
        print(f"{size:5d} {depth:5d} {r['cold_pairs'] / n:16.0f} {r['warm_pairs'] / n:16.0f} "
              f"{1 - r['warm_pairs'] / r['cold_pairs']:6.1%} {statistics.median(r['cold_s']) * 1e3:8.2f} "
              f"{statistics.median(r['warm_s']) * 1e3:8.2f}")


if __name__ == "__main__":
    main()
