"""Fit any shape: the command line's automatic pattern on silhouettes the library draws, and on the paper's apple and flower.

Each target is written as a PNG and fitted by one command with every default,
``python -m ifslib fit TARGET.png --pattern auto --size SIZE -o FIT.json``, in a subprocess (wall
time includes Python's start-up and torch's import). Prints a markdown table (the **attractor's** IoU
and F1, which is what the fit answers, then the IoU of the drawing at the fit's depth K, the
automatic choice, steps, seconds, the JSON's size beside the PNG's) and writes a picture of every
target beside its fit's attractor (the float64 chaos game, 1M points).

    python benchmarks/silhouettes.py                 # 15 silhouettes at 128², the apple and flower at 256²
    python benchmarks/silhouettes.py --only apple flower
    python benchmarks/silhouettes.py --only creature thin --picture figures/silhouettes_thin.png   # the six thin ones

The drawn silhouettes are `silhouettes.gallery` (letters, polygons, blobs) and `silhouettes.thin_gallery`
(creatures with thin limbs, a tail and a hole, and thin letters): solid figures, some of which look porous,
so the table says which kind each was fitted as and, where both were fitted, which was kept.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

import ifslib
from ifslib.core.targets import silhouettes

ROOT = Path(__file__).resolve().parents[1]


def targets(size: int, paper_size: int) -> dict[str, tuple[np.ndarray, int]]:
    """name -> (mask or gray picture, size): the drawn silhouettes, then the paper's two MPEG-7 shapes."""
    drawn = {**silhouettes.gallery(size), **silhouettes.thin_gallery(size)}
    out = {name: (mask.astype(float), size) for name, mask in drawn.items()}
    for name in ("apple", "flower"):
        out[name] = (ifslib.load_target(name, paper_size).picture, paper_size)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128, help="size of the drawn silhouettes (default 128)")
    parser.add_argument("--paper-size", type=int, default=256, help="size of the apple and the flower (default 256)")
    parser.add_argument("--only", nargs="*", default=[], help="names (or prefixes) of the targets to fit")
    parser.add_argument("--out", default="build/silhouettes", help="folder for the PNGs, fits and the picture")
    parser.add_argument("--picture", default="figures/silhouettes.png", help="targets beside their fits")
    args = parser.parse_args()
    out = ROOT / args.out
    out.mkdir(parents=True, exist_ok=True)
    rows, panels = [], []
    for name, (picture, size) in targets(args.size, args.paper_size).items():
        if args.only and not any(name.startswith(p) for p in args.only):
            continue
        stem = name.replace(" ", "_")
        png, fit_json = out / f"{stem}.png", out / f"{stem}.json"
        Image.fromarray((np.clip(picture, 0, 1) * 255).round().astype(np.uint8)).save(png, optimize=True)
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "ifslib", "fit", str(png), "--pattern", "auto", "--size", str(size),
                               "--quiet", "-o", str(fit_json)], capture_output=True, text=True)
        seconds = time.perf_counter() - t0
        if done.returncode:
            print(f"{name}: the fit failed:\n{done.stderr}", file=sys.stderr)
            continue
        target = ifslib.load_target(png, size)
        fitted = ifslib.load_ifs(fit_json)
        m = ifslib.evaluate(fitted, target)
        history = fitted.meta["history"]
        compact = json.dumps({k: v for k, v in json.loads(fit_json.read_text()).items() if k != "meta"})
        rows.append({"name": name, "size": size, "iou": m["attractor_iou"], "f1": m["attractor_f1"],
                     "depth_iou": m["iou"], "depth": fitted.depth, "maps": fitted.meta["pattern"]["maps"],
                     "kind": fitted.meta["pattern"]["kind"], "steps": history["cost"], "seconds": seconds,
                     "both": "decision" in fitted.meta["pattern"],
                     "json": len(compact.encode()), "png": png.stat().st_size})
        r = rows[-1]
        print(f"{name}: attractor IoU {r['iou']:.3f} (drawn at depth {r['depth']}: {r['depth_iou']:.3f}), {r['kind']} "
              f"with {r['maps']} maps, {r['steps']} steps, {seconds:.1f} s", flush=True)
        drawn = ifslib.render(fitted, size, method="chaos", points=1_000_000).numpy()
        panels.append((name, target.mask.astype(float), drawn, m["attractor_iou"]))
    print("\n| target | size | attractor IoU | attractor F1 | IoU at depth K | pattern chosen | steps | wall s | "
          "JSON bytes (no history) | PNG bytes |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['name']} | {r['size']}² | {r['iou']:.3f} | {r['f1']:.3f} | {r['depth_iou']:.3f} (K={r['depth']}) | "
              f"{r['kind']}{' (both fitted)' if r['both'] else ''}, {r['maps']} affine maps | {r['steps']} | {r['seconds']:.1f} | {r['json']:,} | {r['png']:,} |")
    drawn_ones = [r for r in rows if r["size"] == args.size]
    if drawn_ones:
        ious = [r["iou"] for r in drawn_ones]
        secs = [r["seconds"] for r in drawn_ones]
        print(f"\n{len(drawn_ones)} drawn silhouettes at {args.size}²: attractor IoU median {statistics.median(ious):.3f}, "
              f"worst {min(ious):.3f}, {sum(i >= 0.93 for i in ious)} at 0.93 or more; wall time median {statistics.median(secs):.1f} s, longest {max(secs):.1f} s")
    if panels:
        from ifslib.teaching.figures import gallery, save_figure

        names, masks, drawn, ious = zip(*panels)
        fig = gallery([masks, drawn], col_titles=names, row_titles=["target", "attractor"],
                      captions=[[""] * len(panels), [f"IoU {iou:.3f}" for iou in ious]], cell=1.6)
        picture = ROOT / args.picture
        print(f"picture: {save_figure(fig, picture.stem, picture.parent)}")

if __name__ == "__main__":
    main()
