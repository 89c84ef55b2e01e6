"""Deep zooms into the attractor: leaves, time and agreement with the chaos game, from 1x to 1000x.

For the fern and a random affine fractal (``random_ifs(3, 0)``), square windows ``1 / zoom`` wide
centred on a chaos-game point of the attractor (``chaos_game(ifs, 20_000, seed)[-1]`` for each
``--seeds``), at ``--size`` pixels: the seconds of ``render(..., window=w, method="chaos")`` (``--points``
float64 points confined to the window), the certified cut's leaves, the seconds of
``render(ifs, size, "attractor", window=w)`` (medians of ``--repeat``, wall clock and the process's
CPU time, which a shared machine inflates less), and the agreement of the certified field with the
chaos game's (``chaos_field``): the largest ``field - chaos`` (certified <= the tolerance, 0.5 px),
the 99th percentile of ``chaos - field`` (the chaos game's coverage) and the IoU of the two drawn masks.
The load average is printed first: other processes share the cores.

    python benchmarks/zoom.py [--size 256] [--repeat 3] [--seeds 7 11]
"""
from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np
import torch

import ifslib
from ifslib.errors import LeafBudgetError
from ifslib.core.geometry import patterns, random_fractals
from ifslib.core.raster.chaos import chaos_field, chaos_game
from ifslib.core.raster.distance import attractor_leaves_for, distance_field, pixel_size
from ifslib.core.raster.render import render

ZOOMS = (1, 10, 100, 1000)
FIGURES = {"fern": patterns.fern, "random3_0": lambda: random_fractals.random_ifs(3, 0)}


def window(ifs, zoom: float, seed: int) -> tuple[float, float, float, float]:
    """The square ``1 / zoom`` wide around a chaos-game point of the attractor."""
    centre = chaos_game(ifs, 20_000, seed)[-1]
    half = 0.5 / zoom
    return (centre[0] - half, centre[1] - half, centre[0] + half, centre[1] + half)


def timed(call, repeat: int) -> tuple[float, float]:
    """Median wall and CPU seconds of ``repeat`` calls."""
    wall, cpu = [], []
    for _ in range(repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        call()
        wall.append(time.perf_counter() - w0), cpu.append(time.process_time() - c0)
    return statistics.median(wall), statistics.median(cpu)


def row(name: str, zoom: int, seed: int, size: int, repeat: int, points: int) -> str:
    ifs = FIGURES[name]()
    box = window(ifs, zoom, seed)
    px = pixel_size(size, box)
    chaos_wall, chaos_cpu = timed(lambda: render(ifs, size, window=box, method="chaos", points=points), repeat)
    head = f"{name:10s} {zoom:5d}x seed {seed:2d} chaos {chaos_wall:5.2f} s wall {chaos_cpu:5.2f} s cpu | certified "
    try:
        leaves = len(attractor_leaves_for(ifs, size, box))
    except LeafBudgetError:
        return head + "over the leaf budget (4,000,000)"
    with torch.no_grad():
        wall, cpu = timed(lambda: render(ifs, size, "attractor", window=box, device="cpu"), repeat)
        field = distance_field(ifs, size, window=box, device="cpu").double().numpy() / px
    chaos = chaos_field(ifs, size, points, seed=1, window=box).numpy() / px
    drawn, by_chaos = field <= np.sqrt(np.log(2)), chaos <= np.sqrt(np.log(2))  # render >= 0.5 at sigma = 1 px
    iou = (drawn & by_chaos).sum() / max((drawn | by_chaos).sum(), 1)
    return (head + f"{leaves:9,d} leaves {wall:5.2f} s wall {cpu:5.2f} s cpu, field-chaos max "
            f"{(field - chaos).max():+.3f} px, chaos-field q99 {np.quantile(chaos - field, 0.99):.2f} px, "
            f"IoU {iou:.3f}, figure {drawn.mean():.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--seeds", type=int, nargs="+", default=[7, 11])
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores, torch threads {torch.get_num_threads()}, "
          f"ifslib {ifslib.__version__}")
    for name in FIGURES:
        for seed in args.seeds:
            for zoom in ZOOMS:
                print(row(name, zoom, seed, args.size, args.repeat, args.points), flush=True)


if __name__ == "__main__":
    main()
