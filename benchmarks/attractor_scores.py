"""How far a drawing at depth K is from the attractor, and how the certified field agrees with the chaos game.

Run ``python benchmarks/attractor_scores.py``. For each pattern, at ``--size``:

* the IoU of the drawing's mask at depth K = 1..5 against the attractor's mask (the certified
  field within a quarter pixel, `ifslib.metrics.attractor_mask`): the paper's primitives at a fixed
  depth are not the attractor, except where a primitive lies on it (the Koch curve's segment);
* for curves, the Hausdorff distance in pixels between the drawing and the attractor per depth
  (`ifslib.metrics.depth_to_attractor`, the attractor by 1M chaos-game points);
* the certified field (half a pixel) against the float64 chaos game (2M points): the largest
  amount by which it exceeds the distance to the chaos points (the bound says at most 0.5 px) and
  falls below it (at most 0.5 px plus the chaos game's coverage), with the leaves and seconds.
"""
from __future__ import annotations

import argparse
import time

import torch

import ifslib
from ifslib.core.scoring.metrics import attractor_mask, depth_to_attractor, figure_mask
from ifslib.core.raster.chaos import chaos_field
from ifslib.core.raster.distance import attractor_leaves_for

PATTERNS = ("koch", "triangle", "carpet", "rosette6", "fern")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    args = parser.parse_args()
    size = args.size
    print(f"{size}²: IoU of the drawing at depth K against the attractor's mask")
    print(f"{'pattern':10} " + " ".join(f"{'K=' + str(k):>6}" for k in range(1, 6)))
    for name in PATTERNS:
        ifs = ifslib.patterns.by_name(name)
        limit = attractor_mask(ifs, size)
        ious = [ifslib.iou(figure_mask(ifs, size, k), limit) for k in range(1, 6)]
        print(f"{name:10} " + " ".join(f"{v:6.3f}" for v in ious))
    print(f"\nHausdorff distance (px at {size}²) between the Koch curve drawn at depth K and its attractor")
    koch = ifslib.patterns.koch()
    dist = depth_to_attractor(koch, range(0, 7), spacing=0.25 / size)
    print("  " + ", ".join(f"K={k}: {d * size:.2f}" for k, d in enumerate(dist)))
    print(f"\ncertified field (0.5 px) against the float64 chaos game (2M points), {size}²")
    print(f"{'pattern':10} {'leaves':>9} {'field s':>8} {'chaos s':>8} {'over px':>8} {'under px':>9}")
    for name in PATTERNS:
        ifs = ifslib.patterns.by_name(name).to(torch.float64)
        t0 = time.perf_counter()
        field = ifslib.distance_field(ifs, size, "attractor").detach()
        t1 = time.perf_counter()
        chaos = chaos_field(ifs, size, 2_000_000)
        t2 = time.perf_counter()
        leaves = len(attractor_leaves_for(ifs, size))
        print(f"{name:10} {leaves:9,d} {t1 - t0:8.2f} {t2 - t1:8.2f} {float((field - chaos).max()) * size:8.3f} "
              f"{float((chaos - field).max()) * size:9.3f}")


if __name__ == "__main__":
    main()
