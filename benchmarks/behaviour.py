"""Behaviour unchanged: the command line's fits, bit for bit, before and after a change.

Writes the target PNGs once (Koch curves in the first ``--poses`` poses of `cli_poses`, the
silhouettes of `benchmarks/silhouettes.py`, the first ``--fractals`` fractals of
`benchmarks/fractals.py`), a photograph (scikit-image's camera at 256²) and the fern's chaos-game
measure at 64², fits each with every default by ``python -m ifslib fit`` (the photograph by
``python -m ifslib compress --bpp 0.25``; the measure by ``ifslib.measures.fit_measure``, maps and
probabilities, 40 steps) at ``IFSLIB_THREADS=1`` (two at a time, one per core), and compares two
folders: a fit is the same when its points, rules, primitives, depth, fixed points (and a measure
fit's probabilities) are equal as written in the JSON file (Python writes a float's shortest exact
repr, so equal text is equal bits); a compressed file when its bytes are.

    python benchmarks/behaviour.py targets build/behaviour/targets
    python benchmarks/behaviour.py fit build/behaviour/targets build/behaviour/before
    PYTHONPATH=/path/to/other/tree python benchmarks/behaviour.py fit build/behaviour/targets build/behaviour/after
    python benchmarks/behaviour.py compare build/behaviour/before build/behaviour/after
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import torch
from PIL import Image

SAME = ("points", "rules", "primitives", "depth", "fixed")


def write_targets(folder: Path, poses: int, fractals: int) -> None:
    """The PNGs and ``cases.json`` (name -> pattern and size)."""
    sys.path.insert(0, str(Path(__file__).parent))
    import cli_poses
    import silhouettes as silhouette_bench

    import ifslib

    folder.mkdir(parents=True, exist_ok=True)
    cases = {}
    for k, pose in enumerate(cli_poses.random_poses(poses)):
        cli_poses.write_pose(pose, 256, folder / f"koch{k:02d}.png")
        cases[f"koch{k:02d}"] = ("koch", 256)
    for name, (picture, size) in silhouette_bench.targets(128, 256).items():
        stem = name.replace(" ", "_")
        Image.fromarray((np.clip(picture, 0, 1) * 255).round().astype(np.uint8)).save(folder / f"{stem}.png")
        cases[stem] = ("auto", size)
    for i in range(fractals):
        truth = ifslib.random_fractals.random_ifs(2 + i % 4, i)
        picture = ifslib.render(truth, 256, method="chaos", points=2_000_000, seed=i).numpy()
        Image.fromarray(((picture >= 0.5) * 255).astype(np.uint8)).save(folder / f"fractal{i:02d}.png")
        cases[f"fractal{i:02d}"] = ("auto", 256)
    from skimage import data
    Image.fromarray(data.camera()).resize((256, 256), Image.Resampling.LANCZOS).save(folder / "camera.png")
    cases["camera"] = ("compress", 256)
    fern = ifslib.patterns.fern().to(torch.float64)
    fern.probabilities = (0.01, 0.85, 0.07, 0.07)
    from ifslib.measures.measure import chaos_measure
    np.save(folder / "fern_measure.npy", chaos_measure(fern, 64, n=2_000_000))
    cases["fern_measure"] = ("measure", 64)
    (folder / "cases.json").write_text(json.dumps(cases, indent=1))


# The measure fit through its public names only, so that trees of any layout run it.
_MEASURE_FIT = """
import dataclasses, inspect, json, sys
import numpy as np
import ifslib
image = np.load(sys.argv[1])
from ifslib.measures.measure_fit import fit_measure  # where it lives in every tree's layout
options = inspect.signature(fit_measure).parameters["options"].default
options = dataclasses.replace(options, steps=40, fit_maps=True)
fit = fit_measure(ifslib.patterns.fern(), image, options)
saved = json.loads(ifslib.save_ifs(fit.ifs, sys.argv[2]).read_text())
saved["probabilities"] = list(fit.probabilities)
open(sys.argv[2], "w").write(json.dumps(saved))
"""


def _command(target: Path, out: Path, pattern: str, size: int) -> list[str]:
    """The command that fits ``target`` into ``out``: the CLI's fit or compress, or the measure fit."""
    if pattern == "compress":
        return [sys.executable, "-m", "ifslib", "compress", str(target), "--bpp", "0.25", "--quiet", "-o", str(out)]
    if pattern == "measure":
        return [sys.executable, "-c", _MEASURE_FIT, str(target), str(out)]
    return [sys.executable, "-m", "ifslib", "fit", str(target), "--pattern", pattern, "--size", str(size),
            "--quiet", "-o", str(out)]


def fit_one(png: Path, out: Path, pattern: str, size: int) -> tuple[str, float, str]:
    command = _command(png, out, pattern, size)
    t0 = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True, env={**os.environ, "IFSLIB_THREADS": "1"})
    return png.stem, time.perf_counter() - t0, done.stderr.strip()[-300:] if done.returncode else ""


#: A case's target file and output file, by its kind.
_SUFFIX = {"compress": (".png", ".ifsc"), "measure": (".npy", ".json")}
_SUFFIX = {**{kind: (".png", ".json") for kind in ("koch", "auto")}, **_SUFFIX}


def fit_all(targets: Path, out: Path, only: list[str]) -> None:
    cases = json.loads((targets / "cases.json").read_text())
    out.mkdir(parents=True, exist_ok=True)
    chosen = [n for n in cases if not only or any(n.startswith(p) for p in only)]
    with ThreadPoolExecutor(2) as pool:
        jobs = [pool.submit(fit_one, targets / (n + _SUFFIX[cases[n][0]][0]), out / (n + _SUFFIX[cases[n][0]][1]),
                            *cases[n]) for n in chosen]
        for job in jobs:
            name, seconds, error = job.result()
            print(f"{name}: {seconds:.1f} s {'FAILED ' + error if error else ''}", flush=True)


def compare(a: Path, b: Path) -> int:
    names = sorted(p.name for p in a.iterdir() if p.suffix in (".json", ".ifsc"))
    differ = 0
    print(f"| fit | maps | same as {a.name} |\n|---|---|---|")
    for name in names:
        other_path = b / name
        if not other_path.exists():
            print(f"| {name} | | missing in {b.name} |")
            differ += 1
            continue
        if name.endswith(".ifsc"):
            maps, same = "", (a / name).read_bytes() == other_path.read_bytes()
        else:
            one, other = json.loads((a / name).read_text()), json.loads(other_path.read_text())
            maps, same = len(one["rules"]), all(one.get(k) == other.get(k) for k in (*SAME, "probabilities"))
        differ += not same
        print(f"| {Path(name).stem} | {maps} | {'yes' if same else 'NO'} |")
    print(f"\n{len(names) - differ} of {len(names)} fits the same bit for bit")
    return differ


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    t = sub.add_parser("targets", help="write the target PNGs")
    t.add_argument("folder", type=Path)
    t.add_argument("--poses", type=int, default=5)
    t.add_argument("--fractals", type=int, default=10)
    f = sub.add_parser("fit", help="fit every target with the ifslib on the path")
    f.add_argument("targets", type=Path)
    f.add_argument("out", type=Path)
    f.add_argument("--only", nargs="*", default=[], help="names (or prefixes) of the targets to fit")
    c = sub.add_parser("compare", help="compare two folders of fits")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    args = parser.parse_args()
    if args.command == "targets":
        write_targets(args.folder, args.poses, args.fractals)
    elif args.command == "fit":
        fit_all(args.targets, args.out, args.only)
    else:
        sys.exit(1 if compare(args.a, args.b) else 0)


if __name__ == "__main__":
    main()
