"""Throughput of `fit_many` (benchmarks/batch.py: one batched computation) against sequential `ifslib.fit` calls.

The paper's Koch start (`ifslib.patterns.koch_paper(seed)`) fitted to the paper's koch.png with the
multiscale distance loss, seeds 0..B-1. Both sides run the same number of steps per seed from the
same starts; the batched results are checked to equal the sequential ones (bit for bit on CPU).
Sequential fits are timed on ``--sequential`` of the seeds and scaled to all B, which is fair
because every seed costs about the same. Needs the images: set IFSLIB_DATA (``make`` does).

    python benchmarks/fit_many.py [--seeds 32] [--size 128] [--depth 3] [--steps 30] [--device auto]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import torch

import ifslib
from ifslib.core.raster.distance import resolve_device

sys.path.insert(0, str(Path(__file__).parent))
from batch import fit_many  # noqa: E402 - a helper beside this script


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=32)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--depth", type=int, default=3)
    parser.add_argument("--steps", type=int, default=30, help="steps per seed (throughput is per step)")
    parser.add_argument("--sequential", type=int, default=8, help="how many seeds to time sequentially")
    parser.add_argument("--device", default="auto")
    args = parser.parse_args()
    device = resolve_device(args.device)
    target = ifslib.load_target("koch", args.size)
    seeds = list(range(args.seeds))
    kw = {"steps": args.steps, "loss": "multiscale_distance", "options": ifslib.RunOptions(device=str(device)),
          "progress": False}

    def start(seed):
        return ifslib.patterns.koch_paper(seed, depth=args.depth)

    def sync():
        if device.type == "cuda":
            torch.cuda.synchronize()

    print(f"{device} ({torch.get_num_threads()} threads), {args.size}^2, depth {args.depth}, "
          f"{args.seeds} seeds x {args.steps} steps, torch {torch.__version__}")
    ifslib.fit(start(0), target, strategy="plain", **{**kw, "steps": 2})  # warm-up
    sync()
    t0 = time.perf_counter()
    singles = [ifslib.fit(start(s), target, seed=s, strategy="plain", **kw) for s in seeds[:args.sequential]]
    sync()
    sequential = (time.perf_counter() - t0) / args.sequential * args.seeds
    t0 = time.perf_counter()
    many = fit_many(start, target, seeds=seeds, **kw)
    sync()
    batched = time.perf_counter() - t0
    same = all(torch.allclose(a.final.points, b.final.points, atol=1e-5) for a, b in zip(singles, many))
    fit_steps = args.seeds * args.steps
    print("| run | wall s | ms per seed-step | seed-steps/s |")
    print("|---|---|---|---|")
    print(f"| {args.seeds} sequential fits (timed {args.sequential}, scaled) | {sequential:.2f} | "
          f"{1000 * sequential / fit_steps:.2f} | {fit_steps / sequential:.0f} |")
    print(f"| fit_many, one batch of {args.seeds} | {batched:.2f} | {1000 * batched / fit_steps:.2f} | "
          f"{fit_steps / batched:.0f} |")
    print(f"throughput ratio fit_many / sequential: {sequential / batched:.2f}x; "
          f"batched results equal the sequential ones: {same}")


if __name__ == "__main__":
    main()
