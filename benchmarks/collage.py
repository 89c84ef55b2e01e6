"""Barnsley's collage distance as a pre-fit: does lowering it before the rendered fit pay?

For each target at 128², the automatic start with 24 maps at depth 2 is fitted by `ifslib.fit` (the
``auto`` strategy) twice: as it is, and after 200 Adam steps on `ifslib.core.scoring.collage.collage_distance`
(`collage_prefit`). Prints the collage distance before and after, the start's IoU, and each fit's
IoU, steps and seconds (one torch thread: ``IFSLIB_THREADS=1``).

    IFSLIB_THREADS=1 python benchmarks/collage.py
"""
import time

import ifslib
from ifslib.core.targets import silhouettes
from ifslib.studies.prefit import collage_prefit


def main() -> None:
    cases = {"apple": "apple", "flower": "flower", "letter A": silhouettes.letter("A", 128).astype(float),
             "blob 1": silhouettes.blob(128, seed=1).astype(float)}
    print("| target | collage distance: start -> after 200 steps (s) | start IoU -> after | fit IoU from the start | "
          "fit IoU after the pre-fit | s: fit / pre-fit + fit |")
    print("|---|---|---|---|---|---|")
    for name, source in cases.items():
        target = ifslib.load_target(source, 128)
        plan = ifslib.initialize("auto", target, maps=24, depth=2)
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
