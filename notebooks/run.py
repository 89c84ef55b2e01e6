"""Run the notebooks through papermill with a preset: ``python notebooks/run.py --preset paper``.

Executed copies go to ``build/<preset>/`` (ignored by git). Figures go to ``figures/`` for the paper preset
(committed) and to ``build/figures-ci/`` for the ci preset, so a quick run never overwrites them.
The ci preset is each notebook's own parameters cell; ``notebooks/params/<preset>.yaml`` overrides
it per notebook (a section named after the notebook).

``--jobs N`` runs N notebooks at once (default: one per core), the longest first (`LONGEST`), each
in a process of its own with ``IFSLIB_THREADS`` = cores // N unless it is set (fixed, so that
kernels starting together cannot all count the cores as free). On this 2-core machine that is one
thread each; a fit step at 256² runs about as fast on one thread as on two, so two notebooks side
by side take about the time of one.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import papermill
import yaml

from ifslib.paths import figures_dir, repo_root
from ifslib.threads import cores

#: The notebooks that take longest with the paper preset, longest first: they start first.
LONGEST = ("06_", "04_", "02_", "05_", "07_")


def presets(name: str) -> dict:
    """Per-notebook parameters of a preset (``ci``: none, the notebooks' defaults)."""
    path = repo_root() / "notebooks" / "params" / f"{name}.yaml"
    if name == "ci" and not path.exists():
        return {}
    if not path.exists():
        sys.exit(f"no preset {name!r}: {path} does not exist")
    return yaml.safe_load(path.read_text()) or {}


def notebooks(only=()) -> list[Path]:
    """The numbered lessons and the glossary, by name; only those whose names start with one of ``only`` when given."""
    folder = repo_root() / "notebooks"
    books = sorted(folder.glob("[0-9][0-9]_*.ipynb")) + [folder / "glossary.ipynb"]
    return [b for b in books if not only or any(b.stem.startswith(p) for p in only)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="paper", help="paper (default) or ci")
    parser.add_argument("--only", nargs="*", default=[], help="notebook name prefixes, e.g. 02 04")
    parser.add_argument("--jobs", type=int, default=0, help="notebooks run at once (default: one per core)")
    args = parser.parse_args(argv)
    root = repo_root()
    params = presets(args.preset)
    out = root / "build" / args.preset
    save_to = figures_dir() if args.preset == "paper" else root / "build" / f"figures-{args.preset}"
    books = notebooks(args.only)
    out.mkdir(parents=True, exist_ok=True)
    books.sort(key=lambda b: next((k for k, p in enumerate(LONGEST) if b.stem.startswith(p)), len(LONGEST)))
    jobs = max(1, min(args.jobs or cores(), len(books)))
    started = time.perf_counter()

    def execute(book: Path) -> None:
        t0 = time.perf_counter()
        print(f"== {book.name} ({args.preset} preset) started", flush=True)
        values = dict(params.get(book.stem, {}))
        if "save_to" in papermill.inspect_notebook(str(book)):
            values["save_to"] = str(save_to)
        papermill.execute_notebook(str(book), str(out / book.name), cwd=str(book.parent), kernel_name="python3",
                                   parameters=values, progress_bar=jobs == 1)
        print(f"   {book.name}: {time.perf_counter() - t0:.1f} s -> {out.relative_to(root) / book.name}", flush=True)

    if jobs == 1:
        for book in books:
            execute(book)
    else:
        # one process per notebook (this script again, on that notebook only), its output in a log
        env = {**os.environ, "IFSLIB_THREADS": os.environ.get("IFSLIB_THREADS") or str(max(1, cores() // jobs))}
        print(f"{len(books)} notebooks, {jobs} at a time, IFSLIB_THREADS={env['IFSLIB_THREADS']}; logs in "
              f"{out.relative_to(root)}/*.log", flush=True)

        def spawn(book: Path) -> None:
            log = out / f"{book.stem}.log"
            with open(log, "w") as f:
                code = subprocess.call([sys.executable, __file__, "--preset", args.preset, "--only", book.stem,
                                        "--jobs", "1"], stdout=f, stderr=subprocess.STDOUT, env=env)
            text = log.read_text()
            if code:
                print(text[-4000:], flush=True)
                raise RuntimeError(f"{book.name} failed (exit {code}); see {log}")
            print(next(line for line in text.splitlines() if line.strip().startswith(f"{book.name}:")), flush=True)

        with ThreadPoolExecutor(jobs) as pool:
            for future in [pool.submit(spawn, book) for book in books]:
                future.result()  # re-raises a notebook's error
    print(f"all notebooks: {time.perf_counter() - started:.1f} s")
    print(f"figures in {save_to}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
