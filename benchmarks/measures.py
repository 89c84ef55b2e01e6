"""The goals of issue 47, measured: the invariant measure three ways, the measure fit, and box counting.

    python benchmarks/measures.py            # every goal (about 30 min of one core)
    python benchmarks/measures.py --quick    # smaller sizes, a few minutes
    python benchmarks/measures.py --collage  # the fern's and the lopsided triangle's maps from their gray images

Prints, for the fern (Barnsley's probabilities), the Koch curve and the Sierpinski triangle (even
probabilities) and the triangle with (0.5, 0.3, 0.2): the L1 distances of the normalised images of
the chaos game's histogram (10^8 points, with its expected noise), the cylinders' measure and the
deterministic push at 256 px; the fern's probabilities fitted with the maps given, maps and
probabilities fitted from a jittered start, and from the maps the fractal search reads from the
image's support and by the collage search from its gray levels (the fern and the lopsided triangle:
density correlation); box counting on 10^6
chaos-game points against Moran's root for the triangle, the Koch curve and the carpet.
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import torch

import ifslib
from ifslib.measures.measure_fit import (MeasureFitOptions, correlation, fit_measure, fit_measure_from_support,
                                        pool_measure)
from ifslib.measures.measure import (CylinderOptions, MeasureOptions, chaos_measure, cylinder_measure, invariant_measure,
                                   l1_distance, measure_from_maps)
from ifslib.measures import dimension
from ifslib.measures.collage_search import CollageSearchOptions, fit_measure_from_collage

BARNSLEY = (0.01, 0.85, 0.07, 0.07)
#: (pattern, probabilities, supersample): the finer the cells, the closer (the Koch curve's few lit cells are cheap).
MEASURES = (("fern", BARNSLEY, 16), ("koch", None, 32), ("sierpinski_triangle", None, 16),
            ("sierpinski_triangle", (0.5, 0.3, 0.2), 32))


def with_probabilities(name: str, p) -> ifslib.IFS:
    ifs = ifslib.patterns.by_name(name).to(torch.float64)
    ifs.probabilities = p
    return ifs


def measures(size: int, points: int, quick: bool) -> None:
    print(f"invariant measure at {size} px: L1 of normalised images; chaos game of {points:,} points, cylinders "
          "to 1/64 px, push")
    for name, p, supersample in MEASURES:
        ifs = with_probabilities(name, p)
        t0 = time.perf_counter()
        chaos = chaos_measure(ifs, size, n=points)
        t1 = time.perf_counter()
        exact, placed = cylinder_measure(ifs, size, CylinderOptions(smallest=1 / 64))
        t2 = time.perf_counter()
        noise = np.sqrt(2 / np.pi / points) * np.sqrt(exact).sum()  # the histogram's expected L1 noise
        print(f"  {name:>20} {'even' if p is None else p[0]:>5}: cylinders to chaos game "
              f"{l1_distance(exact, chaos):.4f} "
              f"(its noise {noise:.4f}; {placed:.3f} of the mass placed; cylinders {t2 - t1:.1f} s, chaos game "
              f"{t1 - t0:.1f} s)", flush=True)
        for s in ((4,) if quick else (4, supersample)):
            t3 = time.perf_counter()
            with torch.no_grad():
                pushed = invariant_measure(ifs, size, MeasureOptions(supersample=s))
            print(f"  {'':>26} push, supersample {s:>2}: to chaos game {l1_distance(pushed, chaos):.4f}, to cylinders "
                  f"{l1_distance(pushed, exact):.4f} ({time.perf_counter() - t3:.1f} s)", flush=True)


def fits(size: int, steps: int) -> None:
    fern = with_probabilities("fern", BARNSLEY)
    target = chaos_measure(fern, size, n=4_000_000)
    t0 = time.perf_counter()
    given = fit_measure(ifslib.patterns.fern(), target, MeasureFitOptions(steps=steps))
    error = max(abs(a - b) for a, b in zip(given.probabilities, BARNSLEY))
    print(f"fern at {size} px, maps given, from the default probabilities: largest error {error:.4f} "
          f"({', '.join(f'{x:.4f}' for x in given.probabilities)}), {time.perf_counter() - t0:.1f} s", flush=True)
    start = ifslib.patterns.fern().to(torch.float64).jittered(0.015, np.random.default_rng(0))
    with torch.no_grad():
        before = correlation(measure_from_maps(start.maps(), start.measure_probabilities(), size,
                                               MeasureFitOptions().measure), target)
    t0 = time.perf_counter()
    both = fit_measure(start, target, MeasureFitOptions(steps=steps * 4 // 3, map_lr=0.001, fit_maps=True))
    print(f"fern at {size} px, maps and probabilities from the fern's points jittered by 0.015: density "
          f"correlation {before:.3f} -> {both.correlation:.3f}, probabilities "
          f"{', '.join(f'{x:.4f}' for x in both.probabilities)}, {time.perf_counter() - t0:.1f} s", flush=True)


def start_correlation(fit, target: torch.Tensor, size: int) -> float:
    """Density correlation of the maps a fit started from (``fit.start``, with its probabilities) with ``target``."""
    start = fit.start.to(torch.float64)
    with torch.no_grad():
        return correlation(measure_from_maps(start.maps(), start.measure_probabilities(), size,
                                             MeasureFitOptions().measure), target)


def support_fits(size: int, fit_size: int, steps: int) -> None:
    for name, p in (("fern", BARNSLEY), ("sierpinski_triangle", (0.5, 0.3, 0.2))):
        image = chaos_measure(with_probabilities(name, p), size, n=4_000_000)
        t0 = time.perf_counter()
        fit = fit_measure_from_support(image, len(p), MeasureFitOptions(steps=steps, map_lr=0.001, fit_maps=True),
                                       fit_size=fit_size)
        before = start_correlation(fit, pool_measure(image, fit_size), fit_size)
        print(f"{name} from its {size} px support's search, fitted at {fit_size} px: density correlation {before:.3f} "
              f"(search's maps) -> {fit.correlation:.3f}, probabilities "
              f"{', '.join(f'{x:.4f}' for x in fit.probabilities)}"
              f", {time.perf_counter() - t0:.1f} s", flush=True)


def collage_fits(size: int, fit_size: int, steps: int) -> None:
    """The same images, the maps read from their gray levels by the collage search (`fit_measure_from_collage`)."""
    for name, p in (("fern", BARNSLEY), ("sierpinski_triangle", (0.5, 0.3, 0.2))):
        image = chaos_measure(with_probabilities(name, p), size, n=4_000_000)
        t0 = time.perf_counter()
        fit = fit_measure_from_collage(image, len(p), MeasureFitOptions(steps=steps, map_lr=0.001, fit_maps=True),
                                       CollageSearchOptions(size=fit_size))
        target = pool_measure(image, fit_size)
        before = start_correlation(fit, target, fit_size)
        seconds = time.perf_counter() - t0
        drawn = correlation(chaos_measure(fit.ifs.to(torch.float64), fit_size, n=4_000_000), target)
        scales = np.linalg.svd(fit.ifs.maps().detach().numpy()[:, :2, :2])[1]
        print(f"{name} from its {size} px gray image's collage, fitted at {fit_size} px: density correlation "
              f"{before:.3f} (search's maps) -> {fit.correlation:.3f} (the chaos game's histogram of the fit, "
              f"4 million points: {drawn:.3f}), probabilities "
              f"{', '.join(f'{x:.4f}' for x in fit.probabilities)}, singular values "
              f"{', '.join(f'{a:.2f}/{b:.3f}' for a, b in scales)}, {seconds:.1f} s", flush=True)


def dimensions(points: int, finest: int) -> None:
    print(f"box counting on {points:,} chaos-game points, boxes 1/8 .. 1/{finest}")
    for name in ("sierpinski_triangle", "koch", "sierpinski_carpet"):
        ifs = ifslib.patterns.by_name(name)
        moran = dimension.ifs_similarity_dimension(ifs)
        t0 = time.perf_counter()
        fit = dimension.box_counting_points(ifslib.chaos_game(ifs, points), finest=finest)
        print(f"  {name:>20}: Moran {moran:.4f}, box counting {fit.dimension:.4f} +- {fit.stderr:.4f}, "
              f"off by {fit.dimension - moran:+.4f} ({time.perf_counter() - t0:.1f} s)", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes (not the goals' sizes)")
    parser.add_argument("--collage", action="store_true", help="the collage search's fits alone (about 5 min)")
    args = parser.parse_args()
    if args.collage:
        collage_fits(128, 64, 300)
    elif args.quick:
        measures(128, 10_000_000, True), fits(32, 60), support_fits(128, 32, 60), collage_fits(128, 32, 60), dimensions(300_000, 256)
    else:
        measures(256, 100_000_000, False), fits(64, 150), support_fits(128, 64, 200), collage_fits(128, 64, 300), dimensions(1_000_000, 512)


if __name__ == "__main__":
    main()
