"""How often does a Koch fit recover the curve? 20 seeds x the four losses, printed as a table.

Start: the paper's best-fit-line initialization (five points evenly spaced along the target's
principal axis) with seeded jitter U(-jitter, jitter) on every coordinate. Target: the Koch curve
rendered by the library from its known control points, so that the control-point error (up to
similarity and reflection, `ifslib.point_error`) is defined. A fit counts as recovered when the best
points' error is below 0.02. Fits run in parallel processes, one torch thread each; the time per
fit is the wall time of one fit in its process.

    python benchmarks/convergence.py --seeds 20 --steps 1500 --size 128 --depth 3
"""
from __future__ import annotations

import argparse
import statistics
import time
from concurrent.futures import ProcessPoolExecutor


def one(args: tuple) -> dict:
    loss, seed, size, depth, steps, lr, jitter = args
    import torch

    import ifslib

    torch.set_num_threads(1)
    reference = ifslib.patterns.koch(depth=depth)
    target = ifslib.load_target(reference, size)
    start = ifslib.initialize(reference, target, jitter=jitter, seed=seed)
    t0 = time.perf_counter()
    result = ifslib.fit(start, target, steps=steps, lr=lr, loss=loss, seed=seed, progress=False)
    seconds = time.perf_counter() - t0
    m = ifslib.evaluate(result.best, target)
    return {"loss": loss, "seed": seed, "error": ifslib.point_error(result.best, reference), "iou": m["iou"],
            "chamfer": m["chamfer"], "seconds": seconds}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--depth", type=int, default=3)
    parser.add_argument("--lr", type=float, default=0.003)
    parser.add_argument("--jitter", type=float, default=0.05)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    import ifslib

    jobs = [(loss, seed, args.size, args.depth, args.steps, args.lr, args.jitter)
            for loss in ifslib.LOSSES for seed in range(args.seeds)]
    with ProcessPoolExecutor(args.workers) as pool:
        rows = list(pool.map(one, jobs))
    print(f"Koch at {args.size}^2/depth {args.depth}, {args.steps} Adam steps, lr {args.lr}, best-fit-line start "
          f"with jitter U(-{args.jitter}, {args.jitter}), {args.seeds} seeds per loss")
    print("| loss | recovered (point error < 0.02) | median final IoU | median Chamfer (px) | median s/fit |")
    print("|---|---|---|---|---|")
    for loss in ifslib.LOSSES:
        mine = [r for r in rows if r["loss"] == loss]
        ok = sum(r["error"] < 0.02 for r in mine)
        print(f"| {loss} | {ok}/{len(mine)} | {statistics.median(r['iou'] for r in mine):.3f} | "
              f"{statistics.median(r['chamfer'] for r in mine):.2f} | {statistics.median(r['seconds'] for r in mine):.1f} |")


if __name__ == "__main__":
    main()
