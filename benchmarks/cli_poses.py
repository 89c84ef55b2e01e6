"""Does the default `python -m ifslib fit target.png --pattern koch` recover Koch curves in any pose?

Draws the Koch curve rotated, scaled and shifted (a similarity of the library's own curve, rendered
at ``--size``), writes each as a PNG, runs the command-line fit on it with its defaults (the
best-fit-line start and the default strategy) in a subprocess, and judges the fitted IFS on the
image: recovered when the symmetric Chamfer distance to the target mask is at most 1 pixel. The point
error (`ifslib.point_error`, up to similarity and reflection) compares the fitted points with the
posed curve's.

    python benchmarks/cli_poses.py [--size 128] [--steps 1500]
"""
from __future__ import annotations

import argparse
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
from PIL import Image

import ifslib

#: (rotation in degrees, scale, shift x, shift y) of the Koch curve of width 0.8 centred at the origin.
POSES = [(0, 1.0, 0.0, 0.0), (30, 0.7, 0.1, -0.05), (-60, 0.5, -0.15, 0.2), (135, 0.8, 0.0, 0.0),
         (90, 0.4, 0.22, 0.2), (200, 0.6, -0.1, -0.12)]


def posed_koch(angle: float, scale: float, dx: float, dy: float, depth: int = 3) -> ifslib.IFS:
    """The library's Koch curve under the similarity ``x -> scale * R(angle) x + (dx, dy)``."""
    koch = ifslib.patterns.koch(depth=depth).to(torch.float64)
    a = math.radians(angle)
    rot = torch.tensor([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]], dtype=torch.float64)
    return koch.clone(scale * koch.points.detach() @ rot.T + torch.tensor([dx, dy], dtype=torch.float64))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--steps", type=int, default=1500)
    args = parser.parse_args()
    print(f"python -m ifslib fit <png> --pattern koch --size {args.size} --steps {args.steps} (default strategy)")
    print("| rotation | scale | shift | recovered | Chamfer (px) | IoU | point error | self-crossings | s |")
    print("|---|---|---|---|---|---|---|---|---|")
    recovered = 0
    with tempfile.TemporaryDirectory() as tmp:
        for angle, scale, dx, dy in POSES:
            truth = posed_koch(angle, scale, dx, dy)
            png, out = Path(tmp) / "target.png", Path(tmp) / "fitted.json"
            image = ifslib.render(truth, args.size).detach().numpy()
            Image.fromarray((image * 255).round().astype(np.uint8), mode="L").save(png)
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "ifslib", "fit", str(png), "--pattern", "koch", "--size",
                            str(args.size), "--steps", str(args.steps), "--quiet", "-o", str(out)], check=True,
                           capture_output=True)
            seconds = time.perf_counter() - t0
            fitted = ifslib.load_ifs(out)
            m = ifslib.evaluate(fitted, ifslib.load_target(png, args.size))
            ok = m["chamfer"] <= 1.0
            recovered += ok
            print(f"| {angle}° | {scale} | ({dx}, {dy}) | {'yes' if ok else 'no'} | {m['chamfer']:.2f} | "
                  f"{m['iou']:.2f} | {ifslib.point_error(fitted, truth):.3f} | {ifslib.metrics.self_crossings(fitted)} | "
                  f"{seconds:.0f} |", flush=True)
    print(f"recovered {recovered} of {len(POSES)} poses")


if __name__ == "__main__":
    main()
