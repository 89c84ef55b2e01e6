"""Run the notebooks at their teaching or their quick values: ``python notebooks/run.py [--preset quick] [--only 02]``.

Each notebook carries two sets of values (docs/guide/teaching.md, "Stored outputs and CI"):

* **teaching**: its cell tagged ``parameters``, the sizes at which every picture shows what its text
  says. ``--preset teaching`` (the default, ``make figures``) executes the notebook in a fresh kernel
  and **stores the run in the notebook in place** (`store.store`: progress bars dropped, the run
  recorded in ``metadata["ifslib"]["stored"]``), and its figure goes to ``figures/``;
  ``--into DIR`` writes the executed copies and the figures under ``DIR`` instead.
* **quick**: ``metadata["ifslib"]["quick"]``, a dict of the parameters to override (`quick_parameters`),
  what ``make test`` runs. ``--preset quick`` runs them through papermill into ``build/quick/``
  and their figures into ``build/figures-quick/``; it never writes over the stored outputs.

``--jobs N`` runs N notebooks at once (default: one per core), the longest first (`LONGEST`), each
in a process of its own with ``IFSLIB_THREADS`` = cores // N unless it is set (fixed, so that
kernels starting together cannot all count the cores as free). On this 2-core machine that is one
thread each; a fit step at 256² runs about as fast on one thread as on two, so two notebooks side
by side take about the time of one.
"""
from __future__ import annotations

import argparse
import ast
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from ifslib.errors import IFSError

ROOT = Path(__file__).resolve().parents[1]

#: What ``--preset`` takes: the values stored in the notebooks, and the quick ones CI runs.
PRESETS = ("teaching", "quick")

#: The notebooks that take longest at their teaching values, longest first: they start first (the order of
#: their times in `make figures`, two at a time, docs/results/tests.md).
LONGEST = ("04_", "06_", "02_", "08_", "05_", "11_", "07_", "03_", "10_", "09_", "00_tutorial")


def notebooks(only=()) -> list[Path]:
    """Every numbered lesson (``notebooks/[0-9][0-9]_*.ipynb``) and the glossary; those whose names start with one of ``only`` when given."""
    folder = ROOT / "notebooks"
    books = sorted(folder.glob("[0-9][0-9]_*.ipynb")) + [folder / "glossary.ipynb"]
    return [b for b in books if not only or any(b.stem.startswith(p) for p in only)]


def longest_first(books: list[Path]) -> list[Path]:
    """``books`` in `LONGEST`'s order, the others after them in name order."""
    return sorted(books, key=lambda b: next((k for k, p in enumerate(LONGEST) if b.stem.startswith(p)), len(LONGEST)))


def teaching_parameters(path: str | os.PathLike) -> dict:
    """name -> value of the notebook's cell tagged ``parameters`` (its teaching values); it must hold only ``name = literal`` lines."""
    book = json.loads(Path(path).read_text())
    cells = [c for c in book["cells"] if "parameters" in c.get("metadata", {}).get("tags", [])]
    if len(cells) != 1:
        raise IFSError(f"{Path(path).name}: expected one cell tagged 'parameters', found {len(cells)}")
    values = {}
    for node in ast.parse("".join(cells[0]["source"])).body:
        if not (isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(node.targets[0], ast.Name)):
            raise IFSError(f"{Path(path).name}: its parameters cell may hold only `name = literal` lines "
                           f"(line {node.lineno} is not one)")
        try:
            values[node.targets[0].id] = ast.literal_eval(node.value)
        except ValueError:
            raise IFSError(f"{Path(path).name}: parameter {node.targets[0].id} must be a literal "
                           f"(a number, string, list, None...), not an expression") from None
    return values


def quick_parameters(path: str | os.PathLike) -> dict:
    """The overrides of the notebook's quick run, ``metadata["ifslib"]["quick"]`` (``{}`` when it has none).

    Each name must be one of the parameters cell's and its value of the same type (an int may stand
    for a float), so that a renamed parameter cannot be silently ignored by papermill.
    """
    book = json.loads(Path(path).read_text())
    quick = book["metadata"].get("ifslib", {}).get("quick", {})
    if not isinstance(quick, dict):
        raise IFSError(f"{Path(path).name}: metadata['ifslib']['quick'] must be a dict of parameters, got {quick!r}")
    teaching = teaching_parameters(path)
    for name, value in quick.items():
        if name not in teaching:
            raise IFSError(f"{Path(path).name}: quick value {name!r} is not a parameter of its parameters cell "
                           f"({', '.join(teaching)}); rename it in metadata['ifslib']['quick']")
        default = teaching[name]
        if default is not None and value is not None and not isinstance(value, type(default)) \
                and not (isinstance(default, float) and isinstance(value, int)):
            raise IFSError(f"{Path(path).name}: quick value {name}={value!r} should have the type of its teaching "
                           f"value {default!r} ({type(default).__name__})")
    return dict(quick)


def run_quick(path: Path, out: Path, figures: Path, progress_bar: bool = False) -> Path:
    """Execute the notebook at its quick values with papermill into ``out/<name>``, its figure into ``figures``.

    Raises papermill's ``PapermillExecutionError`` (the cell, and the error or failed ``assert``) when a cell fails.
    """
    import papermill

    values = quick_parameters(path)
    if "save_to" in teaching_parameters(path):
        values["save_to"] = str(figures)
    out.mkdir(parents=True, exist_ok=True)
    papermill.execute_notebook(str(path), str(out / path.name), cwd=str(path.parent), kernel_name="python3",
                               parameters=values, progress_bar=progress_bar)
    return out / path.name


def execute(book: Path, preset: str, into: Path | None) -> float:
    """Run one notebook at ``preset`` where `main`'s arguments say; returns seconds."""
    from store import store  # notebooks/store.py: this script's folder is first on sys.path

    root = ROOT
    started = time.perf_counter()
    if preset == "quick":
        run_quick(book, root / "build" / "quick", root / "build" / "figures-quick")
    else:
        store(book, into / book.name if into else book, into / "figures" if into else ROOT / "figures",
              teaching_parameters(book))
    return time.perf_counter() - started


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help="notebook name prefixes, e.g. 02 04 (the same as --only)")
    parser.add_argument("--preset", default="teaching", help="teaching (default: stored in place) or quick (into build/)")
    parser.add_argument("--only", nargs="*", default=[], help="notebook name prefixes, e.g. 02 04")
    parser.add_argument("--into", type=Path, help="teaching preset: write the executed copies and figures here, not in place")
    parser.add_argument("--jobs", type=int, default=0, help="notebooks run at once (default: one per core)")
    parser.add_argument("--no-guide", action="store_true", help=argparse.SUPPRESS)  # a notebook run by the parent
    args = parser.parse_args(argv)
    if args.preset not in PRESETS:
        parser.error(f"no preset {args.preset!r}: use teaching (the values of each parameters cell, stored in "
                     "the notebook) or quick (metadata['ifslib']['quick'], what the tests run)")
    if args.into and args.preset != "teaching":
        parser.error("--into is for the teaching preset; the quick one always runs into build/quick/")
    if args.into:
        args.into = args.into.resolve()  # the kernels run in notebooks/: a relative folder would land there
    books = longest_first(notebooks([*args.names, *args.only]))
    if not books:
        parser.error(f"no notebook starts with {' or '.join([*args.names, *args.only])}")
    root = ROOT
    where = args.into or ("the notebooks, in place" if args.preset == "teaching" else root / "build" / "quick")
    from ifslib.threads import cores  # loads torch: only once there is a notebook to run

    jobs = max(1, min(args.jobs or cores(), len(books)))
    os.environ.setdefault("IFSLIB_THREADS", str(max(1, cores() // jobs)))
    logs = root / "build" / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    print(f"{len(books)} notebooks at their {args.preset} values, {jobs} at a time, "
          f"IFSLIB_THREADS={os.environ['IFSLIB_THREADS']}, into {where}", flush=True)
    started = time.perf_counter()

    def spawn(book: Path) -> None:
        if jobs == 1:
            print(f"   {book.name}: {execute(book, args.preset, args.into):.1f} s", flush=True)
            return
        # one process per notebook (this script again, on that notebook only), its output in a log
        log = logs / f"{args.preset}-{book.stem}.log"
        command = [sys.executable, __file__, "--preset", args.preset, "--only", book.stem, "--jobs", "1", "--no-guide"]
        with open(log, "w") as f:
            code = subprocess.call(command + (["--into", str(args.into)] if args.into else []),
                                   stdout=f, stderr=subprocess.STDOUT)
        text = log.read_text()
        if code:
            print(text[-4000:], flush=True)
            raise RuntimeError(f"{book.name} failed (exit {code}); see {log}")
        print(next(line for line in text.splitlines() if line.strip().startswith(f"{book.name}:")), flush=True)

    with ThreadPoolExecutor(jobs) as pool:
        for future in [pool.submit(spawn, book) for book in books]:
            future.result()  # re-raises a notebook's error
    print(f"all notebooks: {time.perf_counter() - started:.1f} s")
    if args.preset == "teaching" and not args.into and not args.no_guide:   # the guide's table: each run's time
        from store import write_guide_times

        stored = {b.stem: json.loads(b.read_text())["metadata"].get("ifslib", {}).get("stored", {}) for b in notebooks()}
        write_guide_times(root / "docs" / "guide" / "teaching.md",
                          {stem: run["seconds"] for stem, run in stored.items() if "seconds" in run})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
