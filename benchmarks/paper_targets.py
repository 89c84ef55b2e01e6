"""Fit the paper's four target images with the paper's settings and print time and quality.

256^2 targets, depth 3, 1500 Adam steps, lr 0.003 (the paper's settings); the multiscale distance
loss; the best-fit-line start (Koch) or bounding-box start (grids) with jitter U(-0.05, 0.05),
seed 0. Patterns: the Koch curve for koch.png, the carpet for sierpinski.png, and a 3 x 3 grid (as
the paper's repository did for the apple) for the apple and the flower. Needs the images: set
IFSLIB_DATA (``make`` sets it to ../shared/data when that exists).

    python benchmarks/paper_targets.py [--steps 1500] [--size 256]
"""
from __future__ import annotations

import argparse
import time

import ifslib

CASES = [("koch", "koch"), ("sierpinski", "carpet"), ("apple", "grid3"), ("flower", "grid3")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--depth", type=int, default=3)
    parser.add_argument("--loss", default="multiscale_distance")
    parser.add_argument("--strategy", default="plain", help="plain (one run, the default here) or pyramid, ...")
    args = parser.parse_args()
    print(f"{args.size}^2, depth {args.depth}, {args.steps} steps, lr 0.003, loss {args.loss}, strategy {args.strategy}")
    print("| target | pattern | s/fit | ms/step | IoU | F1 | Chamfer (px) |")
    print("|---|---|---|---|---|---|---|")
    for image, pattern in CASES:
        target = ifslib.load_target(image, args.size)
        start = ifslib.initialize(ifslib.patterns.by_name(pattern, args.depth), target, jitter=0.05, seed=0)
        t0 = time.perf_counter()
        result = ifslib.fit(start, target, steps=args.steps, lr=0.003, loss=args.loss, progress=False,
                            strategy=args.strategy)
        seconds = time.perf_counter() - t0
        m = ifslib.evaluate(result.best, target)
        print(f"| {image} | {pattern} | {seconds:.1f} | {1000 * seconds / max(result.history.cost, 1):.1f} | {m['iou']:.3f} | "
              f"{m['f1']:.3f} | {m['chamfer']:.2f} |", flush=True)


if __name__ == "__main__":
    main()
