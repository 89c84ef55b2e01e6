"""The splatting renderer and fit, measured: the 10-map set fitted the literature's way, the fern's gray image, and
a splat step against the exact renderer's.

``--ten`` (default): `random_ifs(10, seed, extent=0.75)` for ``--seeds`` (0-9), drawn as benchmarks/literature.py
draws them (the float64 chaos game, two million points, masked at 0.5), fitted by `ifslib.splatting.fit_splat` with 10
maps from random starts (``--steps``, ``--starts`` seeds of the start, the lowest final loss kept) and scored as
literature.py scores (``--start search``: from the fractal search's maps instead, padded to 10 with jittered copies of
the largest, ``--pad copies``, or with random maps, ``--pad random``; the seconds include the search's): recovered
when the fitted attractor has IoU >= 0.85 and Chamfer <= 1 px (`ifslib.evaluate`), and the literature's PSNR, SSIM, F1
and IoU after the 12.5 % crop (LPIPS needs AlexNet's weights, which cannot be fetched here: not computed).
``--fern``: Barnsley's fern's gray image (the chaos game's histogram at 128², four million points, as
benchmarks/measures.py) fitted at 64² from the support search's maps (`fit_measure_from_support`), then by the splat
fit, scored by density correlation at 64². ``--timing``: one splat step (forward and backward) against one
step of the exact renderer (the depth-3 drawing, 1,000 leaves, forward and backward) at ``--timing-sizes`` (the
certified attractor of these maps needs more than the 4,000,000-leaf budget at 256 px already: not timed).

    IFSLIB_THREADS=1 python benchmarks/splatting.py --ten --size 256 --steps 600
    IFSLIB_THREADS=1 python benchmarks/splatting.py --ten --size 256 --steps 600 --start search --pad copies
    IFSLIB_THREADS=1 python benchmarks/splatting.py --timing --timing-sizes 256 1024
    python benchmarks/splatting.py --ten --size 1024 --device cuda      # on a GPU
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import torch

import ifslib
from ifslib.core.targets.target import target_from_mask
from ifslib.splatting import SplatFitOptions, SplatOptions, fit_splat, splat_measure
from ifslib.splatting.config import POINTS_PER_PIXEL

sys.path.insert(0, str(Path(__file__).parent))
from literature_scores import literature_scores  # noqa: E402 - a helper beside this script
from literature import EXTENT, POINTS  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


#: A start padded with copies of its own maps (`padded_with_copies`): each copy's translation
#: moves by up to this much (plane units) and its rotation by up to this share of a turn. Larger, copies that start
#: apart from their originals (less alike, so less likely to stay stacked) but farther from the figure's detail.
PAD_JITTER = 0.03


def padded_with_copies(maps: torch.Tensor, m: int, jitter: float, generator: torch.Generator) -> torch.Tensor:
    """``maps`` topped up to ``m`` with jittered copies of the largest ones, in turn.

    A set of few maps that covers a figure of many (the fractal search's) lays one copy over two or more of the
    figure's; a copy of it, moved a little, is a second map where one is missing, which the fit can pull apart.

    Parameters
    ----------
    maps : torch.Tensor
        ``(k, 3, 3)`` maps, ``k >= 1``.
    m : int
        The number of maps wanted; ``maps`` itself when ``m <= k``.
    jitter : float
        Each copy's translation moves by up to this much (plane units), its rotation by up to ``jitter`` times
        2 pi (radians).
    generator : torch.Generator

    Returns
    -------
    torch.Tensor
        ``(max(k, m), 3, 3)`` float64.
    """
    maps = torch.as_tensor(maps, dtype=torch.float64)
    k = len(maps)
    if m <= k:
        return maps
    order = torch.argsort(torch.linalg.svdvals(maps[:, :2, :2])[:, 0], descending=True)
    copies = maps[order[torch.arange(m - k) % k]].clone()
    noise = 2 * torch.rand(m - k, 3, generator=generator, dtype=torch.float64) - 1
    angle = noise[:, 2] * jitter * 2 * math.pi
    c, s = angle.cos(), angle.sin()
    turn = torch.stack([torch.stack([c, -s], -1), torch.stack([s, c], -1)], -2)
    copies[:, :2, :2] = copies[:, :2, :2] @ turn
    copies[:, :2, 2] += jitter * noise[:, :2]
    return torch.cat([maps, copies])


def searched_start(target, seed: int, pad: str) -> tuple[torch.Tensor | None, dict]:
    """The fractal search's chosen maps (`ifslib.automatic.fractal.search`), padded to 10 with jittered copies of the
    largest (``pad="copies"``; with random maps placed on the figure, ``"random"``, fit_splat pads them itself), and
    the search's own row: its maps, its attractor's IoU at the target's size, its seconds."""
    from ifslib.automatic.fractal import search
    t0 = time.perf_counter()
    found = search(target, seed=seed, progress=False)
    seconds = time.perf_counter() - t0
    maps = torch.as_tensor(found.maps, dtype=torch.float64)
    maps = torch.cat([maps, torch.tensor([[[0.0, 0.0, 1.0]]], dtype=torch.float64).expand(len(maps), 1, 3)], 1)
    iou = ifslib.evaluate(ifslib.patterns.affine(maps, dtype=torch.float64), target, depth="attractor")["iou"]
    if pad == "copies":
        maps = padded_with_copies(maps, 10, PAD_JITTER, torch.Generator().manual_seed(seed))
    return maps, {"search_maps": len(found.maps), "search_iou": iou, "search_seconds": seconds}


def ten(args) -> list[dict]:
    rows = []
    screened = SplatFitOptions()
    how = (f"after the best of {screened.starts} random starts screened {screened.screen_steps} steps at "
           f"{args.size // 4}²" if args.start == "random" else
           "from the fractal search's maps padded to 10 with "
           + ("jittered copies" if args.pad == "copies" else "random maps"))
    print(f"fit_splat, 10 maps, {args.steps} steps ({how}), {args.starts} run(s) a fractal, {args.size}², "
          f"device {args.device}, threads {torch.get_num_threads()}")
    print("| fractal | search maps | search IoU | attractor IoU | attractor Chamfer (px) | recovered | s "
          "| reselections | PSNR | SSIM | F1 | IoU |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    tuned = {k: v for k, v in (("anneal_noise", args.anneal_noise), ("reseed_every", args.reseed_every),
                                ("map_lr", args.map_lr)) if v is not None}
    if tuned:
        print("options changed from the defaults:", tuned)
    for seed in args.seeds:
        truth = ifslib.random_fractals.random_ifs(10, seed, extent=EXTENT)
        picture = ifslib.render(truth, args.size, method="chaos", points=POINTS, seed=seed).numpy()
        target = target_from_mask(picture >= 0.5, f"ten{seed}")
        t0 = time.perf_counter()
        start, searched = searched_start(target, seed, args.pad) if args.start == "search" else (None, {})
        fits = [fit_splat(target, maps=10, start=start,
                          options=SplatFitOptions(steps=args.steps, seed=s, device=args.device, **tuned))
                for s in range(args.starts)]
        fit = min(fits, key=lambda f: float(np.mean(f.losses[-20:])))
        seconds = time.perf_counter() - t0
        m = ifslib.evaluate(fit.ifs, target, attractor=True)
        drawn = ifslib.render(fit.ifs, args.size, method="chaos", points=POINTS).numpy()
        lit = literature_scores(drawn, picture)
        row = {"fractal": f"ten{seed}", "iou": m["attractor_iou"], "chamfer": m["attractor_chamfer"],
               "seconds": seconds, "reseeds": fit.reseeds, "start": args.start, **searched,
               **{f"cropped_{k}": v for k, v in lit.items()}}
        row["recovered"] = row["iou"] >= 0.85 and row["chamfer"] <= 1
        rows.append(row)
        print(f"| ten{seed} | {searched.get('search_maps', '-')} | "
              f"{searched['search_iou']:.3f} | " if searched else f"| ten{seed} | - | - | ", end="")
        print(f"{row['iou']:.3f} | {row['chamfer']:.2f} | {'yes' if row['recovered'] else 'no'} | "
              f"{seconds:.0f} | {fit.reseeds} | {lit['psnr']:.2f} | {lit['ssim']:.3f} | {lit['f1']:.3f} | "
              f"{lit['iou']:.3f} |", flush=True)
    n = len(rows)
    means = ", ".join(f"{k.upper()} {statistics.fmean(r['cropped_' + k] for r in rows):.3f}"
                      for k in ("psnr", "ssim", "f1", "iou"))
    print(f"\nrecovered {sum(r['recovered'] for r in rows)} of {n}; attractor IoU median "
          f"{statistics.median(r['iou'] for r in rows):.3f}; median "
          f"{statistics.median(r['seconds'] for r in rows):.0f} s a fit; cropped 12.5 %, means: {means}")
    return rows


def fern(args) -> None:
    from ifslib.measures.measure import chaos_measure, measure_from_maps
    from ifslib.measures.measure_fit import (MeasureFitOptions, correlation, fit_measure_from_support,
                                             pool_measure)
    ifs = ifslib.patterns.by_name("fern").to(torch.float64)
    ifs.probabilities = (0.01, 0.85, 0.07, 0.07)
    image = chaos_measure(ifs, 128, n=4_000_000)
    target = pool_measure(image, 64).numpy()
    t0 = time.perf_counter()
    start = fit_measure_from_support(image, 4, MeasureFitOptions(steps=args.fern_push_steps, map_lr=0.001,
                                                                 fit_maps=True), fit_size=64)
    t1 = time.perf_counter()
    options = SplatFitOptions(steps=args.steps, points_per_pixel=args.fern_points, anneal_noise=0.0, reseed_every=0,
                              map_lr=args.fern_lr, probability_lr=0.01, depth=12)
    fit = fit_splat(target, start=start.ifs, options=options)
    with torch.no_grad():  # scored as fit_measure scores (the push at its options), and by the chaos game
        pushed = measure_from_maps(fit.ifs.maps(), fit.ifs.measure_probabilities(), 64, MeasureFitOptions().measure)
    chaos = chaos_measure(fit.ifs, 64, n=4_000_000)
    print(f"fern, 64² from 128² (4 million points): the support search + push fit ({args.fern_push_steps} steps) "
          f"{start.correlation:.3f} in {t1 - t0:.0f} s; then the splat fit ({args.steps} steps) "
          f"{correlation(pushed, target):.3f} (chaos game's histogram: {correlation(chaos, target):.3f}) in "
          f"{fit.seconds:.0f} s; probabilities "
          f"{', '.join(f'{p:.4f}' for p in fit.ifs.probabilities)}")


def timed(step, repeats: int) -> float:
    step()  # warm-up
    if torch.cuda.is_available():
        torch.cuda.synchronize()
    t0 = time.perf_counter()
    for _ in range(repeats):
        step()
    if torch.cuda.is_available():
        torch.cuda.synchronize()
    return (time.perf_counter() - t0) / repeats


def timing(args) -> None:
    truth = ifslib.random_fractals.random_ifs(10, 0, extent=EXTENT)
    print(f"one step, 10-map ten0, device {args.device}, threads {torch.get_num_threads()}")
    print("| size | splat points | splat fwd+bwd (s) | exact depth 3 fwd+bwd (s) |")
    print("|---|---|---|---|")
    for size in args.timing_sizes:
        points = round(POINTS_PER_PIXEL * size * size)
        maps = truth.to(torch.float32).maps().detach().to(args.device).requires_grad_(True)
        p = truth.measure_probabilities().float().to(args.device)

        def splat_step():
            splat_measure(maps, p, size, SplatOptions(points=points)).square().sum().backward()

        work = truth.to(torch.float32)
        work.points.requires_grad_(True)

        def exact_step():
            ifslib.render(work, size, 3).square().sum().backward()

        print(f"| {size} | {points:,} | {timed(splat_step, 3):.3f} | {timed(exact_step, 2):.3f} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ten", action="store_true", help="the 10-map set (the default when nothing else is asked)")
    parser.add_argument("--fern", action="store_true", help="the fern's gray image")
    parser.add_argument("--timing", action="store_true", help="a splat step against the exact renderer's")
    parser.add_argument("--size", type=int, default=256, help="target size of --ten (default 256)")
    parser.add_argument("--steps", type=int, default=600, help="steps of each fit (default 600)")
    parser.add_argument("--starts", type=int, default=1, help="random starts a fractal, the best kept (default 1)")
    parser.add_argument("--start", default="random", choices=["random", "search"],
                        help="--ten's starts: random maps (screened), or the fractal search's maps padded to 10")
    parser.add_argument("--pad", default="copies", choices=["copies", "random"],
                        help="with --start search: pad with jittered copies of the largest maps, or random maps")
    parser.add_argument("--seeds", type=int, nargs="+", default=list(range(10)), help="fractals of --ten (0-9)")
    parser.add_argument("--anneal-noise", type=float, default=None, help="--ten's annealing noise (default the fit's)")
    parser.add_argument("--reseed-every", type=int, default=None, help="--ten's reselection period (0: never)")
    parser.add_argument("--map-lr", type=float, default=None, help="--ten's map learning rate (default the fit's)")
    parser.add_argument("--timing-sizes", type=int, nargs="+", default=[256, 1024])
    parser.add_argument("--fern-push-steps", type=int, default=200, help="the push fit's steps before the splat fit")
    parser.add_argument("--fern-points", type=float, default=64.0, help="points per pixel of the fern's splat fit")
    parser.add_argument("--fern-lr", type=float, default=0.001, help="map_lr of the fern's splat fit")
    parser.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    parser.add_argument("--out", default="build/splatting", help="folder for the rows (JSON)")
    args = parser.parse_args()
    if not (args.ten or args.fern or args.timing):
        args.ten = True
    if args.timing:
        timing(args)
    if args.fern:
        fern(args)
    if args.ten:
        rows = ten(args)
        out = ROOT / args.out
        out.mkdir(parents=True, exist_ok=True)
        changed = "".join(f"_{k}{getattr(args, k)}" for k in ("anneal_noise", "reseed_every", "map_lr")
                          if getattr(args, k) is not None)
        (out / f"ten_{args.size}_{args.start}{changed}.json").write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
