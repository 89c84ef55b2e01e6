"""The learned first guess (issue 65), measured as the literature measures: each fractal of a set drawn by the
float64 chaos game at ``--size``, guessed by `ifslib.learned.guess`, then refined by the splat fit
(`ifslib.splatting.fit_splat`, every default but its steps) for each of ``--steps``; beside it the same fit from
random starts (its own screening of random starts) with the same steps. A fractal is **recovered** when the
attractor has IoU >= 0.85 and Chamfer <= 1 px against the target (`ifslib.evaluate`). One thread, one fit at a time;
the seconds are the guess's and the fit's, not the drawing's.

    python benchmarks/learned.py --set ten                  # the 10-map set (random_ifs(10, seed), seeds 0-9)
    python benchmarks/learned.py --set random --count 20    # the random benchmark's (benchmarks/fractals.py): 2 + s % 4 maps
    python benchmarks/learned.py --set many                 # the literature's many class (6-10 maps)
    python benchmarks/learned.py --steps 0 30 300 --random   # add the random-start rows
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import torch

import ifslib
from ifslib.core.targets.target import target_from_mask
from ifslib.learned import guess
from ifslib.splatting import SplatFitOptions, fit_splat

sys.path.insert(0, str(Path(__file__).parent))
from samplers import literature_ifs  # noqa: E402 - a helper beside this script

EXTENT = 0.75
POINTS = 2_000_000


def truths(name: str, seeds: list[int]) -> list[tuple[str, ifslib.IFS]]:
    if name == "ten":
        return [(f"ten{s}", ifslib.random_fractals.random_ifs(10, s, extent=EXTENT)) for s in seeds]
    if name == "random":
        return [(f"random{s}", ifslib.random_fractals.random_ifs(2 + s % 4, s, extent=EXTENT)) for s in seeds]
    return [(f"{name}{s}", literature_ifs(name, 6 + s % 5 if name == "many" else 3 + s % 3, s, extent=EXTENT))
            for s in seeds]


def score(ifs: ifslib.IFS, target) -> tuple[float, float]:
    m = ifslib.evaluate(ifs, target, depth="attractor")
    return m["iou"], m["chamfer"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", default="ten", choices=["ten", "random", "many", "stem", "spiral", "overlap"])
    parser.add_argument("--seeds", type=int, nargs="*")
    parser.add_argument("--count", type=int, default=10)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--steps", type=int, nargs="+", default=[0, 300])
    parser.add_argument("--random", action="store_true", help="also fit from random starts with the same steps")
    parser.add_argument("--known-maps", action="store_true",
                        help="give the guess the true number of maps, as the random starts are (default: its own count)")
    parser.add_argument("--refine", default="fit", choices=["fit", "polish"],
                        help="the guess refined by the splat fit's defaults (coarse to fine, annealing, reselection), "
                             "or by the automatic path's polish (the target's size, no annealing or reselection)")
    args = parser.parse_args()
    torch.set_num_threads(1)
    rows = []
    for label, truth in truths(args.set, args.seeds or list(range(args.count))):
        picture = ifslib.render(truth, args.size, method="chaos", points=POINTS, seed=0).numpy() >= 0.5
        target = target_from_mask(picture, label)
        t0 = time.perf_counter()
        start = guess(target, len(truth.rules) if args.known_maps else None)
        guessed = time.perf_counter() - t0
        for steps in args.steps:
            starts = [("guess", start)] + ([("random", None)] if args.random and steps else [])
            for kind, begin in starts:
                t0 = time.perf_counter()
                if steps == 0:
                    ifs = begin
                else:
                    polish = kind == "guess" and args.refine == "polish"
                    options = SplatFitOptions(steps=steps, map_lr=0.005, anneal_noise=0.0, reseed_every=0, kind="support",
                                              coarse_to_fine=False) if polish else SplatFitOptions(steps=steps)
                    ifs = fit_splat(target, len(truth.rules) if begin is None else None, begin, options).ifs
                seconds = time.perf_counter() - t0 + (guessed if kind == "guess" else 0.0)
                iou, chamfer = score(ifs, target)
                rows.append((label, kind, steps, len(truth.rules), len(ifs.rules), iou, chamfer, seconds))
                print(f"{label:>10} {kind:>6} {steps:>5} steps: maps {len(truth.rules)} -> {len(ifs.rules)}, "
                      f"IoU {iou:.3f}, Chamfer {chamfer:.2f} px, {seconds:.1f} s", flush=True)
    print(f"\n{args.set} at {args.size}² ({len(rows)} rows); recovered = IoU >= 0.85 and Chamfer <= 1 px")
    for kind in ("guess", "random"):
        for steps in args.steps:
            got = [r for r in rows if r[1] == kind and r[2] == steps]
            if got:
                won = sum(r[5] >= 0.85 and r[6] <= 1 for r in got)
                print(f"{kind:>6} + {steps:>5} steps: recovered {won} of {len(got)}, IoU median "
                      f"{statistics.median(r[5] for r in got):.3f}, median {statistics.median(r[7] for r in got):.2f} s")


if __name__ == "__main__":
    main()
