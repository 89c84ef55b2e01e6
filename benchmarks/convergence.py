"""The convergence study: success rate, steps and time per fit over strategy x gradient x start x loss.

Each cell is fitted from ``--seeds`` seeded starts to the paper's ``koch.png`` (or ``--target
rendered``: the library's Koch curve) and judged on the image: recovered when the symmetric Chamfer
distance to the target mask is at most 1 pixel at the target's size. Runs on a process pool
of ``--workers`` processes (one torch thread each) by default, ``--scheduler ADDRESS`` for a running
Dask cluster, ``--scheduler serial`` in this process. Prints a markdown table and writes every fit to a CSV.

    python benchmarks/convergence.py --seeds 30 --size 256 --strategies plain multistart \\
        --gradients exact paper --inits paper line --losses multiscale_distance

``--cell STRATEGY:GRADIENT:INIT:LOSS`` (repeatable) runs exactly the cells given instead of the
product of the lists, all on one pool:

    python benchmarks/convergence.py --seeds 8 --size 128 --cell plain:exact:paper:multiscale_distance \\
        --cell plain:paper:paper:multiscale_distance --cell multistart:exact:line:multiscale_distance
"""
from __future__ import annotations

import argparse
import csv
import itertools
import json
import os
import time
from pathlib import Path

from ifslib.core.fitting.strategies import STRATEGIES
from ifslib.studies.sweep import Cell, Setup, summarize, sweep, table


def write_csv(rows: list[dict], path: str | os.PathLike) -> Path:
    """Write the per-fit rows as CSV (the fitted points as a JSON list)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({**r, "points": json.dumps(r["points"])} if "points" in r else r for r in rows)
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=30)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--depth", type=int, default=3)
    parser.add_argument("--steps", type=int, default=1500)
    parser.add_argument("--target", default="koch", help="a paper image name, or 'rendered'")
    parser.add_argument("--strategies", nargs="*", default=["plain"], choices=STRATEGIES)
    parser.add_argument("--gradients", nargs="*", default=["exact", "paper"])
    parser.add_argument("--inits", nargs="*", default=["paper", "line"])
    parser.add_argument("--losses", nargs="*", default=["multiscale_distance"])
    parser.add_argument("--cell", action="append", default=[], metavar="STRATEGY:GRADIENT:INIT:LOSS",
                        help="run this cell (repeatable); replaces the product of the lists above")
    parser.add_argument("--tol", type=float, help="early stop of the single-run strategies (default: off, every step spent; pyramid keeps its own)")
    parser.add_argument("--patience", type=int, help="early stop window in steps (with --tol)")
    parser.add_argument("--batch", type=int, default=2, help="seeds per Dask task")
    parser.add_argument("--scheduler", default="local", help="'local' (default), 'serial', or a scheduler address")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--csv", default="build/convergence.csv")
    args = parser.parse_args()

    if args.cell:
        parts = [c.split(":") for c in args.cell]
        bad = [c for c, p in zip(args.cell, parts) if len(p) != 4]
        if bad:
            parser.error(f"--cell takes STRATEGY:GRADIENT:INIT:LOSS, got {bad[0]!r}")
        cells = [Cell(*p) for p in parts]
    else:
        cells = [Cell(s, g, i, loss) for i, g, loss, s in
                 itertools.product(args.inits, args.gradients, args.losses, args.strategies)]
    setup = Setup(target=args.target, size=args.size, depth=args.depth, steps=args.steps, tol=args.tol,
                  patience=args.patience)
    done: list[dict] = []
    t0 = time.perf_counter()
    total = len(cells) * args.seeds

    def save(rows: list[dict]) -> None:  # keep every finished fit on disk as the sweep goes
        done.extend(rows)
        write_csv(done, args.csv)
        for r in rows:
            print(f"[{len(done)}/{total}] {r['strategy']} {r['gradient']} {r['init']} {r['loss']} seed {r['seed']}: "
                  f"Chamfer {r['chamfer']:.2f} px, {r['crossings']} crossings, {r['seconds']:.0f} s", flush=True)

    rows = sweep(cells, list(range(args.seeds)), setup, batch=args.batch, scheduler=args.scheduler,
                 workers=args.workers, on_rows=save)
    stop = f"early stop tol {args.tol}, patience {args.patience}" if args.tol is not None else "each strategy's own stop"
    print(f"target {args.target} at {args.size}^2/depth {args.depth}, step budget {args.steps} per run, {stop}, "
          f"lr 0.003, {args.seeds} seeds per cell; recovered = symmetric Chamfer <= 1 px; {time.perf_counter() - t0:.0f} s")
    print(table(summarize(rows)))
    print(f"every fit: {write_csv(rows, args.csv)}")


if __name__ == "__main__":
    main()
