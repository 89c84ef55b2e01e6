"""Time to a recovered fit: `python -m ifslib fit target.png --pattern koch` on Koch curves in random poses.

Draws the library's Koch curve rotated (0-360°), scaled (0.5-0.9) and shifted (inside the frame) by a
seeded generator, writes each as a PNG at ``--size``, and runs the command-line fit on it in a
subprocess with its defaults (the best-fit-line start; the default strategy, or each ``--strategy``
given, on the same poses). The wall time is that of the whole command (start-up, loading, fitting,
writing), with ``IFSLIB_THREADS`` set to ``--threads``. A fit is recovered when the symmetric Chamfer
distance between the fitted IFS's **attractor** and the target mask is at most 1 pixel (the Chamfer
distance of its drawing at depth 3 is printed beside it); the point error
(`ifslib.point_error`, up to similarity and reflection) compares the fitted points with the posed
curve's.

    python benchmarks/cli_poses.py [--size 256] [--poses 20] [--strategy pyramid --strategy multistart]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import torch
from PIL import Image

import ifslib


def posed_koch(angle: float, scale: float, dx: float, dy: float, depth: int = 3) -> ifslib.IFS:
    """The library's Koch curve under the similarity ``x -> scale * R(angle) x + (dx, dy)``."""
    koch = ifslib.patterns.koch(depth=depth).to(torch.float64)
    a = math.radians(angle)
    rot = torch.tensor([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]], dtype=torch.float64)
    return koch.clone(scale * koch.points.detach() @ rot.T + torch.tensor([dx, dy], dtype=torch.float64))


def random_poses(n: int, seed: int = 2026) -> list[tuple[float, float, float, float]]:
    """``n`` poses (rotation in degrees, scale, shift x, shift y).

    The curve (width ``0.8 * scale``, centred at the origin) stays whole in the frame in any rotation:
    its circle of radius ``0.4 * scale`` about the shift lies at least 0.02 inside ``[-0.5, 0.5]^2``.
    """
    rng = np.random.default_rng(seed)
    poses = []
    for _ in range(n):
        angle, scale = rng.uniform(0, 360), rng.uniform(0.5, 0.9)
        room = 0.48 - 0.4 * scale
        poses.append((angle, scale, rng.uniform(-room, room), rng.uniform(-room, room)))
    return poses


def fit_command(png: Path, out: Path, size: int, strategy: str | None = None) -> list[str]:
    """The command line of a default CLI fit of ``png`` (the Koch pattern) written to ``out``."""
    command = [sys.executable, "-m", "ifslib", "fit", str(png), "--pattern", "koch", "--size", str(size), "--quiet",
               "-o", str(out)]
    return command + ([] if strategy is None else ["--strategy", strategy])


def write_pose(pose: tuple[float, float, float, float], size: int, png: Path) -> ifslib.IFS:
    """Render the posed Koch curve at ``size`` into ``png``; returns the posed IFS (the truth)."""
    truth = posed_koch(*pose)
    image = ifslib.render(truth, size).detach().numpy()
    Image.fromarray((image * 255).round().astype(np.uint8), mode="L").save(png)
    return truth


def fit_once(png: Path, out: Path, size: int, strategy: str | None, threads: int | str) -> float:
    """Run the CLI fit; returns its wall time in seconds."""
    command = fit_command(png, out, size, strategy)
    t0 = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, env={**os.environ, "IFSLIB_THREADS": str(threads)})
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--poses", type=int, default=20)
    parser.add_argument("--first", type=int, default=0, help="skip the first poses (to split a run)")
    parser.add_argument("--strategy", action="append", help="strategies to compare (default: the CLI's default)")
    parser.add_argument("--threads", default="2", help="IFSLIB_THREADS of the fits: a number or auto")
    parser.add_argument("--json", help="also write every row here")
    args = parser.parse_args()
    strategies = args.strategy or [None]
    rows = []
    print(f"python -m ifslib fit <png> --pattern koch --size {args.size} [--strategy S], IFSLIB_THREADS={args.threads}")
    print("| pose | rotation | scale | shift | strategy | recovered | attractor Chamfer (px) | depth-3 Chamfer (px) | "
          "point error | steps | s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for k, (angle, scale, dx, dy) in enumerate(random_poses(args.poses)):
            if k < args.first:
                continue
            png = Path(tmp) / "target.png"
            truth = write_pose((angle, scale, dx, dy), args.size, png)
            target = ifslib.load_target(png, args.size)
            for strategy in strategies:
                out = Path(tmp) / "fitted.json"
                seconds = fit_once(png, out, args.size, strategy, args.threads)
                fitted = ifslib.load_ifs(out)
                m = ifslib.evaluate(fitted, target)
                history = fitted.meta.get("history", {})
                row = dict(pose=k, angle=angle, scale=scale, dx=dx, dy=dy, strategy=history.get("strategy", "plain"),
                           recovered=m["attractor_chamfer"] <= 1.0, chamfer=m["attractor_chamfer"],
                           depth_chamfer=m["chamfer"], point_error=ifslib.point_error(fitted, truth),
                           steps=history.get("cost"), seconds=seconds)
                rows.append(row)
                print(f"| {k} | {angle:.0f}° | {scale:.2f} | ({dx:.2f}, {dy:.2f}) | {row['strategy']} | "
                      f"{'yes' if row['recovered'] else 'no'} | {m['attractor_chamfer']:.2f} | {m['chamfer']:.2f} | "
                      f"{row['point_error']:.3f} | "
                      f"{row['steps']} | {seconds:.1f} |", flush=True)
                if args.json:
                    Path(args.json).write_text(json.dumps(rows, indent=1))
    for strategy in sorted({r["strategy"] for r in rows}):
        mine = [r for r in rows if r["strategy"] == strategy]
        print(f"{strategy}: recovered {sum(r['recovered'] for r in mine)} of {len(mine)}; wall time median "
              f"{statistics.median(r['seconds'] for r in mine):.1f} s (min {min(r['seconds'] for r in mine):.1f}, max "
              f"{max(r['seconds'] for r in mine):.1f}); steps median {statistics.median(r['steps'] for r in mine):.0f}")


if __name__ == "__main__":
    main()
