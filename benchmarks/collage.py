"""Barnsley's collage distance as a pre-fit: does lowering it before the rendered fit pay?

For each target at 128², the automatic start with 24 maps at depth 2 is fitted by `ifslib.fit` (the
``auto`` strategy) twice: as it is, and after 200 Adam steps on `ifslib.core.scoring.collage.collage_distance`
(`collage_prefit`, here: a benchmark's own, the library keeps one optimizer of the collage, the
fractal search's). Prints the collage distance before and after, the start's IoU, and each fit's
IoU, steps and seconds (one torch thread: ``IFSLIB_THREADS=1``).

    IFSLIB_THREADS=1 python benchmarks/collage.py
"""
import math
import time

import torch

import ifslib
from ifslib.core.scoring.collage import collage_distance
from ifslib.core.targets import silhouettes


def collage_prefit(ifs: ifslib.IFS, target: ifslib.Target, steps: int = 200, lr: float = 0.003, n: int = 2000,
                   seed: int = 0) -> tuple[ifslib.IFS, list[float]]:
    """Adam on the free control points, minimizing `collage_distance`; a step that stops a map contracting ends it.

    Returns
    -------
    IFS
        The points with the lowest collage distance seen (a copy).
    list of float
        The collage distance at every step.
    """
    if steps < 0:
        raise ifslib.IFSError(f"steps must be >= 0, got {steps}")
    if not (isinstance(lr, (int, float)) and lr > 0 and math.isfinite(lr)):
        raise ifslib.IFSError(f"lr must be a finite number > 0, got {lr!r}")
    work = ifs.clone()
    opt = torch.optim.Adam([work.points], lr=lr)
    history, best, best_points = [], math.inf, work.points.detach().clone()
    for _ in range(steps):
        try:
            work.check_contractive(max(work.depth, 1))
        except ifslib.IFSError:
            break
        opt.zero_grad(set_to_none=True)
        value = collage_distance(work, target, n, seed)
        value.backward()
        if work.fixed:
            work.points.grad[list(work.fixed)] = 0
        history.append(value.item())
        if history[-1] < best:
            best, best_points = history[-1], work.points.detach().clone()
        opt.step()
    return ifs.clone(best_points), history


def main() -> None:
    cases = {"apple": "apple", "flower": "flower", "letter A": silhouettes.letter("A", 128).astype(float),
             "blob 1": silhouettes.blob(128, seed=1).astype(float)}
    print("| target | collage distance: start -> after 200 steps (s) | start IoU -> after | fit IoU from the start | "
          "fit IoU after the pre-fit | s: fit / pre-fit + fit |")
    print("|---|---|---|---|---|---|")
    for name, source in cases.items():
        target = ifslib.load_target(source, 128)
        plan = ifslib.discover(target, maps=24, depth=2)
        start = plan.start
        t0 = time.perf_counter()
        pre, history = collage_prefit(start, target, steps=200, lr=0.003)
        prefit_s = time.perf_counter() - t0
        fits = []
        for s in (plan, plan.with_start(pre)):  # the automatic fit of each start
            t0 = time.perf_counter()
            result = ifslib.fit(s, target, loss="multiscale_distance", progress=False)
            fits.append((ifslib.evaluate(result.best, target)["iou"], time.perf_counter() - t0))
        print(f"| {name} | {history[0]:.2e} -> {min(history):.2e} ({prefit_s:.1f}) | "
              f"{ifslib.evaluate(start, target)['iou']:.3f} -> {ifslib.evaluate(pre, target)['iou']:.3f} | "
              f"{fits[0][0]:.3f} | {fits[1][0]:.3f} | {fits[0][1]:.1f} / {prefit_s + fits[1][1]:.1f} |", flush=True)


if __name__ == "__main__":
    main()
