"""Run every notebook of a folder as a student would, with nothing of the repository beside it.

    python run_edition.py FOLDER [--timeout S] [--jobs N]

Run by the Python of the environment under test (a fresh venv with the wheel of ifslib and
requirements-student.txt): each notebook is executed in FOLDER with that Python's own kernel, its
quick values (``metadata["ifslib"]["quick"]``) injected after its parameters cell when it has them
(the teaching values run in the students' venv under nbval: ``.ci/wheel.sh``). ``--jobs`` notebooks
run at once (one per core by default, as ``notebooks/student.py`` runs them), each its own kernel (give
each one thread: ``IFSLIB_THREADS=1``).
An nbgrader test cell may raise ``AssertionError`` (an unanswered exercise); any other error fails
the run. Needs only nbformat and nbclient, which JupyterLab brings.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import nbformat
from nbclient import NotebookClient


def with_quick_values(book):
    """``book`` with its quick values injected after the parameters cell (as papermill injects them)."""
    quick = book.metadata.get("ifslib", {}).get("quick", {})
    where = [i for i, c in enumerate(book.cells) if "parameters" in c.metadata.get("tags", [])]
    if quick and where:
        cell = nbformat.v4.new_code_cell("".join(f"{k} = {v!r}\n" for k, v in quick.items()))
        cell.metadata["tags"] = ["injected-parameters"]
        book.cells.insert(where[0] + 1, cell)
    return book


def is_test(cell) -> bool:
    """nbgrader's test cell: graded, not an answer."""
    grader = cell.metadata.get("nbgrader", {})
    return cell.cell_type == "code" and bool(grader.get("grade")) and not grader.get("solution")


def execute(path: Path, timeout: int):
    """The notebook at ``path`` executed at its quick values in its own folder, errors kept in its outputs:
    ``(the executed notebook, seconds)``. ``notebooks/student.py --check`` runs the student edition with it too."""
    started = time.perf_counter()
    book = with_quick_values(nbformat.read(path, as_version=4))
    NotebookClient(book, timeout=timeout, kernel_name="python3", allow_errors=True,
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    return book, time.perf_counter() - started


def run(path: Path, timeout: int) -> tuple[list[str], float]:
    """Execute one notebook in its folder: the errors that are not an unanswered exercise's test, and seconds."""
    book, seconds = execute(path, timeout)
    problems = []
    for index, cell in enumerate(book.cells):
        for output in cell.get("outputs", []):
            if output.output_type == "error" and not (is_test(cell) and output.ename == "AssertionError"):
                problems.append(f"cell {index} raised {output.ename}: {output.evalue[:300]}")
    return problems, seconds


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--timeout", type=int, default=900, help="seconds a cell may run")
    parser.add_argument("--jobs", type=int, default=len(os.sched_getaffinity(0)),
                        help="notebooks run at once (default: one per core)")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs must be at least 1, got {args.jobs}")
    paths = sorted(args.folder.glob("*.ipynb"))
    failed = 0
    with ThreadPoolExecutor(args.jobs) as pool:  # each notebook's work is in its kernel's process
        runs = pool.map(lambda p: run(p, args.timeout), paths)
        for path, (problems, seconds) in zip(paths, runs):
            failed += bool(problems)
            print(f"{path.name}: {'FAILED' if problems else 'ran'} in {seconds:.0f} s", flush=True)
            for problem in problems:
                print(f"    {problem}", flush=True)
    print(f"{len(paths) - failed} passed, {failed} failed (notebooks run from {args.folder})", flush=True)
    return 1 if failed or not paths else 0


if __name__ == "__main__":
    sys.exit(main())
