"""Real fractals: the command line's automatic pattern on random IFS fractals of 2 to 5 maps.

Fractal ``i`` has ``2 + i % 4`` maps and seed ``i`` (`ifslib.random_fractals.random_ifs`, the sampler of
Anderson and Farrell), drawn by the float64 chaos game (two million points) at ``--size`` and
written as a PNG; each is fitted by one command with every default,
``python -m ifslib fit TARGET.png --pattern auto --size SIZE -o FIT.json``, in a subprocess (wall
time includes start-up). A fractal is **recovered** when the fitted IFS's attractor has IoU >= 0.85
and symmetric Chamfer distance <= 1 px against the target mask (`ifslib.evaluate`'s attractor
scores). Prints one row per fractal (maps true and found, attractor IoU and Chamfer, seconds,
and, for a fractal not recovered, why: read as a shape, too many maps, IoU or Chamfer short), then the summary against the goals, and writes a picture of
the targets beside the attractors found.

    python benchmarks/fractals.py                  # 50 fractals at 256²
    python benchmarks/fractals.py --count 8        # the first 8
    python benchmarks/fractals.py --only 30 35     # fractals 30 and 35 (after a change that only they feel)
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

import ifslib
from ifslib.teaching.figures import box_outlines, draw_outlines, gallery, save_figure

ROOT = Path(__file__).resolve().parents[1]


def why(row: dict) -> str:
    """Why a fractal was not recovered, from what the fit reports."""
    reasons = [] if row["kind"] == "fractal" else [
        f"fitted as a fractal and as a {row['kind']}, the {row['kind']} kept" if row.get("both")
        else f"the search gave up: fitted as a {row['kind']}"]
    if row["found"] > row["maps"] + 1:
        reasons.append(f"{row['found']} maps for {row['maps']}")
    if row["iou"] < 0.85:
        reasons.append(f"IoU {row['iou']:.3f} < 0.85")
    if row["chamfer"] > 1:
        reasons.append(f"Chamfer {row['chamfer']:.2f} px > 1")
    if row["seconds"] > 60:
        reasons.append(f"{row['seconds']:.0f} s > 60 s")
    return "; ".join(reasons)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=50, help="number of fractals (default 50)")
    parser.add_argument("--only", type=int, nargs="+", default=None,
                        help="fit only these fractals (numbers below --count); the summary is of them")
    parser.add_argument("--size", type=int, default=256, help="target size in pixels (default 256)")
    parser.add_argument("--out", default="build/fractals", help="folder for the PNGs and fits")
    parser.add_argument("--picture", default="figures/fractals.png", help="targets beside the attractors found")
    args = parser.parse_args()
    chosen = list(range(args.count)) if args.only is None else args.only
    if any(not 0 <= i < args.count for i in chosen):
        parser.error(f"--only takes fractal numbers from 0 to {args.count - 1}")
    out = ROOT / args.out
    out.mkdir(parents=True, exist_ok=True)
    rows, panels = [], []
    print(f"python -m ifslib fit <png> --pattern auto --size {args.size}, IFSLIB_THREADS={os.environ.get('IFSLIB_THREADS', 'auto')}")
    print("| fractal | maps | found | attractor IoU | attractor Chamfer (px) | s | recovered | why not |")
    print("|---|---|---|---|---|---|---|---|")
    for i in chosen:
        maps, seed = 2 + i % 4, i
        truth = ifslib.random_fractals.random_ifs(maps, seed)
        picture = ifslib.render(truth, args.size, method="chaos", points=2_000_000, seed=seed).numpy()
        png, fit_json = out / f"fractal{i:02d}.png", out / f"fractal{i:02d}.json"
        Image.fromarray(((picture >= 0.5) * 255).astype(np.uint8)).save(png)
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "ifslib", "fit", str(png), "--pattern", "auto", "--size",
                               str(args.size), "--quiet", "-o", str(fit_json)], capture_output=True, text=True)
        seconds = time.perf_counter() - t0
        if done.returncode:
            print(f"| {i} | {maps} | - | - | - | {seconds:.1f} | no | the fit failed: {done.stderr.strip()[-200:]} |")
            continue
        target = ifslib.load_target(png, args.size)
        fitted = ifslib.load_ifs(fit_json)
        m = ifslib.evaluate(fitted, target, attractor=True)
        row = {"fractal": i, "maps": maps, "found": len(fitted.rules), "iou": m["attractor_iou"],
               "chamfer": m["attractor_chamfer"], "seconds": seconds, "kind": fitted.meta.get("pattern", {}).get("kind"),
               "both": "decision" in fitted.meta.get("pattern", {})}
        row["recovered"] = row["iou"] >= 0.85 and row["chamfer"] <= 1
        rows.append(row)
        print(f"| {i} | {maps} | {row['found']} | {row['iou']:.3f} | {row['chamfer']:.2f} | {seconds:.1f} | "
              f"{'yes' if row['recovered'] else 'no'} | {'' if row['recovered'] else why(row)} |", flush=True)
        panels.append((f"#{i}: {maps} maps", target.mask.astype(float),
                       ifslib.render(fitted, args.size, method="chaos", points=1_000_000).numpy(),
                       f"{row['found']} maps, IoU {row['iou']:.2f}", box_outlines(fitted, target.mask)))
    if not rows:
        return
    n = len(rows)
    recovered = sum(r["recovered"] for r in rows)
    few = sum(r["found"] <= r["maps"] + 1 for r in rows)
    print(f"\n{n} fractals at {args.size}²: recovered {recovered} of {n} ({100 * recovered / n:.0f} %; goal >= 90 %), "
          f"median {statistics.median(r['seconds'] for r in rows):.1f} s a fit (goal <= 60 s), maps found <= true + 1 "
          f"in {few} of {n} ({100 * few / n:.0f} %; goal >= 80 %); attractor IoU median "
          f"{statistics.median(r['iou'] for r in rows):.3f}")
    names, targets, found, captions, outlines = zip(*panels[:12])
    fig = gallery([targets, found], col_titles=names, row_titles=["target, copies found", "attractor found"],
                  captions=[[""] * len(names), list(captions)], cell=1.6)
    for ax, quads in zip(fig.axes[:len(names)], outlines):
        draw_outlines(ax, quads)
    picture = ROOT / args.picture
    print(f"picture: {save_figure(fig, picture.stem, picture.parent)}")


if __name__ == "__main__":
    main()
