"""Time and peak memory of one attractor fit step: depth-free distance field + loss + backward.

Run ``python benchmarks/attractor_step.py`` (``--device cuda`` on a GPU). For each pattern and size it
prints the number of leaves of the certified cut (`ifslib.core.geometry.attractor`: every branch cut where
it is within half a pixel of the attractor), the median time of ``--repeat`` warm steps (the field,
the multiscale distance loss against the pattern's own attractor, backward), and the peak memory:
each configuration runs in a fresh subprocess, and the figure is the growth of the process's peak
resident set (``ru_maxrss``) over its size just before the first step (on CUDA:
``torch.cuda.max_memory_allocated``). ``sampled`` rows draw 65,536 leaves of the cut at random
(``method="sampled"``, what fits of overlapping shapes use) instead of the whole cut.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys

from stepping import timed_steps

CONFIGS = [("koch", "fast", 256), ("triangle", "fast", 256), ("carpet", "fast", 256), ("fern", "fast", 256),
           ("fern", "sampled", 256), ("koch", "fast", 512), ("triangle", "fast", 512), ("carpet", "fast", 512),
           ("fern", "sampled", 512)]


def one(name: str, method: str, size: int, repeat: int, device: str) -> dict:
    import torch

    import ifslib
    from ifslib.core.raster.distance import attractor_leaves_for

    ifs = ifslib.patterns.by_name(name)
    with torch.no_grad():
        target = ifslib.load_target(ifslib.render(ifs, size, "attractor").cpu().numpy() >= 0.5, size)
    jitter = torch.Generator().manual_seed(0)
    with torch.no_grad():
        ifs.points += (torch.rand(ifs.points.shape, generator=jitter) - 0.5) * 0.01  # a step away from the answer
    leaves = 65536 if method == "sampled" else len(attractor_leaves_for(ifs, size))

    def step():
        ifs.points.grad = None
        d = ifslib.distance_field(ifs, size, "attractor", method=method, device=device)
        ifslib.loss(d, target, "multiscale_distance").backward()
        if d.is_cuda:
            torch.cuda.synchronize()

    seconds, peak = timed_steps(step, repeat, device)
    return {"seconds": seconds, "peak_bytes": peak, "leaves": leaves}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm steps timed per configuration")
    parser.add_argument("--device", default="cpu", help="cpu or cuda")
    parser.add_argument("--one", nargs=3, metavar=("PATTERN", "METHOD", "SIZE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(one(args.one[0], args.one[1], int(args.one[2]), args.repeat, args.device)))
        return
    import torch

    import ifslib

    print(f"one attractor fit step (field + multiscale distance loss + backward), torch {torch.__version__}, "
          f"device {args.device}, {ifslib.threads.torch.get_num_threads()} threads")
    print(f"{'pattern':9} {'method':8} {'size':>5} {'leaves':>10} {'ms/step':>9} {'peak MB':>9}")
    for name, method, size in CONFIGS:
        out = subprocess.run([sys.executable, __file__, "--one", name, method, str(size), "--repeat", str(args.repeat),
                              "--device", args.device], capture_output=True, text=True)
        if out.returncode:
            print(f"{name:9} {method:8} {size:5d}   failed: {out.stderr.strip().splitlines()[-1]}")
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"{name:9} {method:8} {size:5d} {r['leaves']:10,d} {1e3 * r['seconds']:9.1f} {r['peak_bytes'] / 2**20:9.1f}",
              flush=True)


if __name__ == "__main__":
    main()
