"""Time and peak memory of one fit step: distance field + a loss + backward.

Run ``python benchmarks/render.py`` (or ``make bench``). Each configuration runs in a fresh
subprocess so that its peak memory is its own: on CPU the figure is the growth of the process's
peak resident set (``ru_maxrss``) over its size just before the step; on CUDA it is
``torch.cuda.max_memory_allocated``. Times are the median of ``--repeat`` warm steps after one
warm-up step. The brute force is skipped where keeping every leaf at every pixel would exceed the
memory budget (the paper's algorithm), and the estimate is printed instead.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys

from stepping import timed_steps

CONFIGS = [("fast", 256, 3), ("brute", 256, 3), ("fast", 512, 6), ("brute", 512, 6), ("fast", 1024, 7)]
# bytes per (pixel, leaf) pair that an unchunked autograd brute force keeps (about 10 float32 tensors)
PAPER_BYTES_PER_PAIR = 40


def one(method: str, size: int, depth: int, repeat: int, device: str) -> dict:
    import torch

    import ifslib

    torch.manual_seed(0)
    ifs = ifslib.patterns.koch(depth=depth)
    target = torch.zeros(size, size)

    def step():
        ifs.points.grad = None
        d = ifslib.distance_field(ifs, size, method=method, device=device)
        loss = (torch.relu(d) - target.to(d.device)).square().mean()
        loss.backward()
        if d.is_cuda:
            torch.cuda.synchronize()

    seconds, peak = timed_steps(step, repeat, device)
    leaves = ifslib.expand(ifs, depth)
    pairs = ifslib.nearest_leaf(leaves, size).pairs if method == "fast" else size * size * len(leaves)
    return {"seconds": seconds, "peak_bytes": peak, "pairs": pairs}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="warm steps timed per configuration")
    parser.add_argument("--device", default="cpu", help="cpu or cuda")
    parser.add_argument("--budget-gb", type=float, default=20.0, help="skip brute force above this estimate")
    parser.add_argument("--one", nargs=3, metavar=("METHOD", "SIZE", "DEPTH"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        method, size, depth = args.one[0], int(args.one[1]), int(args.one[2])
        print(json.dumps(one(method, size, depth, args.repeat, args.device)))
        return
    import torch

    print(f"one Koch fit step (distance field + loss + backward), torch {torch.__version__}, device {args.device}, "
          f"{torch.get_num_threads()} threads")
    print(f"{'method':6} {'size':>5} {'depth':>5} {'leaves':>7} {'s/step':>9} {'peak MB':>9} {'pairs evaluated':>16}")
    results = {}
    for method, size, depth in CONFIGS:
        leaves = 4 ** depth
        if method == "brute":
            need = size * size * leaves * PAPER_BYTES_PER_PAIR
            if need > args.budget_gb * 2**30:
                print(f"{method:6} {size:5d} {depth:5d} {leaves:7d}   skipped: every leaf at every pixel kept for autograd "
                      f"would need ~{need / 2**30:.0f} GB (> {args.budget_gb:.0f} GB)")
                continue
        out = subprocess.run([sys.executable, __file__, "--one", method, str(size), str(depth), "--repeat",
                              str(args.repeat), "--device", args.device], capture_output=True, text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        results[(method, size, depth)] = r
        print(f"{method:6} {size:5d} {depth:5d} {leaves:7d} {r['seconds']:9.4f} {r['peak_bytes'] / 2**20:9.1f} {r['pairs']:16,d}")
    f, b = results.get(("fast", 256, 3)), results.get(("brute", 256, 3))
    if f and b:
        print(f"fast vs brute at 256^2/depth 3: {b['seconds'] / f['seconds']:.1f}x faster")


if __name__ == "__main__":
    main()
