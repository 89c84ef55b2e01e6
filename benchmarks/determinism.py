"""The same fit at every thread count: the command line's fitted files compared across ``IFSLIB_THREADS``.

Each case is one ``python -m ifslib fit`` command, run in a subprocess at each thread count asked
for (``--threads 1 2``, and ``busy``: the default ``auto`` beside a process that keeps both cores
busy, so the thread count follows the load mid-fit). The fitted files are compared with their
timings taken out (the ``seconds`` of each stage and search row, which no two runs share): a row
says ``identical`` when the rest of the files are equal byte for byte, else the largest difference
of a control point and whether the discrete choices (pattern, number of maps, strategy's stages)
agree.

    python benchmarks/determinism.py                    # Koch, a silhouette and fractals 0-3
    python benchmarks/determinism.py --cases fractal5   # one case
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

import ifslib

ROOT = Path(__file__).resolve().parents[1]

TIMING_KEYS = {"seconds", "wall_seconds", "time", "elapsed"}


def scrub(value):
    """The file's content without wall-clock timings (the only fields two runs of one fit may not share)."""
    if isinstance(value, dict):
        return {k: scrub(v) for k, v in value.items() if k not in TIMING_KEYS}
    if isinstance(value, list):
        return [scrub(v) for v in value]
    return value


def target_png(case: str, out: Path, size: int) -> Path:
    """Write the case's target image and return its path."""
    png = out / f"{case}.png"
    if case.startswith("fractal"):
        i = int(case[len("fractal"):])
        truth = ifslib.random_fractals.random_ifs(2 + i % 4, i)
        picture = ifslib.render(truth, size, method="chaos", points=2_000_000, seed=i).numpy()
    else:
        picture = ifslib.load_target(case, size).mask.astype(float)
    Image.fromarray(((picture >= 0.5) * 255).astype(np.uint8)).save(png)
    return png


def busy_process() -> subprocess.Popen:
    """A process keeping two cores busy (two torch threads of matrix products) until killed."""
    code = ("import torch; torch.set_num_threads(2); a = torch.randn(800, 800)\n"
            "while True: a = torch.tanh(a @ a)")
    return subprocess.Popen([sys.executable, "-c", code])


def run(png: Path, pattern: str, size: int, threads: str, out: Path) -> tuple[dict, float]:
    """One CLI fit at ``threads`` (a count, or ``busy``); the scrubbed file and the wall time."""
    env = dict(os.environ, IFSLIB_THREADS="auto" if threads == "busy" else threads)
    result = out / f"{png.stem}-{threads}.json"
    load = busy_process() if threads == "busy" else None
    try:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "ifslib", "fit", str(png), "--pattern", pattern, "--size", str(size),
                        "--quiet", "-o", str(result)], env=env, check=True, capture_output=True, text=True)
        seconds = time.perf_counter() - t0
    finally:
        if load is not None:
            load.kill()
            load.wait()
    return scrub(json.loads(result.read_text())), seconds


def compare(a: dict, b: dict) -> str:
    """``identical``, or how two scrubbed files differ."""
    if a == b:
        return "identical"
    same_choice = (a.get("meta", {}).get("pattern", {}).get("maps") == b.get("meta", {}).get("pattern", {}).get("maps")
                   and len(a["rules"]) == len(b["rules"]))
    pa, pb = np.array(a["points"]), np.array(b["points"])
    gap = float(np.abs(pa - pb).max()) if pa.shape == pb.shape else float("inf")
    return f"differs: points within {gap:.2e}, same number of maps: {same_choice}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=["koch", "apple", "fractal0", "fractal1", "fractal2", "fractal3"],
                        help="koch, sierpinski, apple, flower (the paper's images) or fractalN (benchmarks/fractals.py's)")
    parser.add_argument("--threads", nargs="+", default=["1", "2", "busy"], help="thread counts, or busy")
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--out", default="build/determinism")
    args = parser.parse_args()
    out = ROOT / args.out
    out.mkdir(parents=True, exist_ok=True)
    print(f"python -m ifslib fit <png> --size {args.size}; files compared without their timings")
    print("| case | pattern | " + " | ".join(f"{t} (s)" for t in args.threads) + " | against " + args.threads[0] + " |")
    print("|---|---|" + "---|" * len(args.threads) + "---|")
    for case in args.cases:
        pattern = "koch" if case == "koch" else "auto"
        png = target_png(case, out, args.size)
        files, times = zip(*(run(png, pattern, args.size, t, out) for t in args.threads))
        verdicts = sorted({compare(files[0], f) for f in files[1:]})
        print(f"| {case} | {pattern} | " + " | ".join(f"{s:.1f}" for s in times) + f" | {'; '.join(verdicts)} |",
              flush=True)


if __name__ == "__main__":
    main()
