"""What the tangent-plane bound saves the nearest-leaf search, along the notebooks' fits.

Each configuration is a fit of notebooks 02 and 04 at 256², depth 3 (Adam on the multiscale distance
loss, lr 0.003, from the notebook's start). At every step the search runs twice on the same leaves:
with the tangent planes (`ifslib.nearest_leaf`, as fits use it) and with the Lipschitz bound alone
(`has_slope` patched to say no). Both must give the same winners and distances (checked at every step). Printed:
(block, leaf) pairs evaluated a step and the median time of each search.

Run ``python benchmarks/search_bound.py [--steps N] [--size S]``. Times are wall-clock medians with
torch's current thread count (set ``IFSLIB_THREADS``); on a shared machine they are noisy, the pair
counts are not.
"""
from __future__ import annotations

import argparse
import statistics
import time
from unittest.mock import patch

import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster import nearest
from ifslib.core.raster.leaf_distance import sdf_pairs

#: name -> (target, start): the starts of notebooks 02 (a pattern placed on the target) and 04 (the paper's
#: jittered Koch start, seeds 1 and 3 stall in the stored run)
CONFIGS = {
    "koch (02)": ("koch", lambda t: ifslib.initialize(ifslib.patterns.by_name("koch", depth=3), t)),
    "koch paper seed 1 (04)": ("koch", lambda t: ifslib.patterns.koch_paper(1, depth=3)),
    "koch paper seed 3 (04)": ("koch", lambda t: ifslib.patterns.koch_paper(3, depth=3)),
    "flower rosette6 (02)": ("flower", lambda t: ifslib.initialize(ifslib.patterns.by_name("rosette6", depth=3), t)),
    "apple grid3, boxes (02)": ("apple", lambda t: ifslib.initialize(ifslib.patterns.by_name("grid3", depth=3), t)),
}


def measure(name: str, size: int, steps: int) -> dict:
    """Both searches at every one of ``steps`` Adam steps of configuration ``name``."""
    source, make = CONFIGS[name]
    target = ifslib.load_target(source, size)
    ifs = make(target)
    x, y = ifslib.pixel_centres(size, "cpu", ifs.points.dtype)
    opt = torch.optim.Adam([ifs.points], lr=0.003)
    out = {"pairs": 0, "plain_pairs": 0, "s": [], "plain_s": []}
    for _ in range(steps):
        opt.zero_grad()
        leaves = expand(ifs, ifs.depth)
        t0 = time.perf_counter()
        found = ifslib.nearest_leaf(leaves, size)
        t1 = time.perf_counter()
        with patch.object(nearest, "has_slope", lambda table, kind: False):
            plain = ifslib.nearest_leaf(leaves, size)
        t2 = time.perf_counter()
        if not (torch.equal(found.leaf, plain.leaf) and torch.equal(found.distance, plain.distance)):
            raise AssertionError(f"{name}: the two bounds give different winners")
        out["pairs"] += found.pairs
        out["plain_pairs"] += plain.pairs
        out["s"].append(t1 - t0)
        out["plain_s"].append(t2 - t1)
        field = sdf_pairs(leaves, x, y, found.leaf).view(size, size)
        ifslib.loss(field, target, "multiscale_distance").backward()
        if ifs.fixed:
            ifs.points.grad[list(ifs.fixed)] = 0
        opt.step()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=30, help="fit steps per configuration")
    parser.add_argument("--size", type=int, default=256, help="target size in pixels")
    args = parser.parse_args()
    print(f"nearest-leaf search, tangent planes vs the Lipschitz bound alone, along {args.steps} fit steps "
          f"at {args.size}², depth 3, {torch.get_num_threads()} threads")
    print(f"{'configuration':<26} {'leaves':>6} {'pairs/step':>11} {'Lipschitz':>10} {'saved':>6} "
          f"{'ms':>7} {'Lipschitz ms':>13}")
    for name in CONFIGS:
        r = measure(name, args.size, args.steps)
        n = len(r["s"])
        leaves = len(expand(CONFIGS[name][1](ifslib.load_target(CONFIGS[name][0], args.size)), 3))
        print(f"{name:<26} {leaves:6d} {r['pairs'] / n:11.0f} {r['plain_pairs'] / n:10.0f} "
              f"{1 - r['pairs'] / r['plain_pairs']:6.1%} {statistics.median(r['s']) * 1e3:7.1f} "
              f"{statistics.median(r['plain_s']) * 1e3:13.1f}")


if __name__ == "__main__":
    main()
