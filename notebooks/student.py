"""Write the student edition of the notebooks: ``python notebooks/student.py [OUT] [--check]``.

The notebooks in ``notebooks/`` are the instructor's edition: each exercise cell holds its worked
answer between nbgrader's markers, at the indentation of the code it belongs to::

    T3 = None   # your answer: a 3 x 3 list or array
    ### BEGIN SOLUTION
    T3 = [[1 / 6, r3 / 6, 1 / 2], [-r3 / 6, 1 / 6, r3 / 6], [0, 0, 1]]
    ### END SOLUTION
    ifslib.exercises.check_koch_map(T3, 3);

The student edition (``OUT``, default ``build/student/``) holds every notebook of ``notebooks/``:

- a notebook with an exercise (a marked block, a cell tagged ``exercise`` or one with nbgrader
  metadata) is rewritten: each marked block becomes the one statement ``...  # YOUR CODE HERE`` at the
  block's indentation (valid Python everywhere: the check that follows then sees the ``None`` above
  it, or a function that returns None, and answers "not yet"), every output and execution count is
  cleared (a stored output can show an answer) and all metadata is kept, nbgrader's included, so
  that nbgrader can grade the edition;
- the others are copied as they are, stored outputs included: they hold no solution, their figures
  come from runs of minutes, and the student gets the whole course in one folder.

A notebook needs nothing from ``notebooks/`` at run time (the presets of ``notebooks/params`` are
passed in by ``run.py``; the images come from ``IFSLIB_DATA`` or are downloaded), so nothing else is
copied. Markers that do not pair up (a BEGIN without END, an END without BEGIN, a BEGIN inside a
block) are refused, naming the notebook and the cell, and nothing is written.

``--check`` then executes each rewritten notebook top to bottom (nbclient, a fresh python3 kernel, a
temporary copy, ``IFSLIB_THREADS=1``) and fails unless no cell raises, every exercise cell prints
"not yet", no cell prints "correct." and no solution line of the instructor's edition is left in the
student's. It prints one line per notebook with its run time. It also fails on a notebook that calls
``ifslib.exercises.check_*`` but marks no exercise: copied as it is, it would give its answers away.

    python notebooks/student.py                  # write build/student/
    python notebooks/student.py --check          # write it, then execute and check it
    python notebooks/student.py /tmp/class --check
"""
from __future__ import annotations

import argparse
import copy
import os
import re
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
DEFAULT_OUT = ROOT / "build" / "student"

#: nbgrader's delimiters: a comment line (any number of comment characters) holding only the words.
BEGIN = re.compile(r"^(?P<indent>\s*)#+\s*BEGIN SOLUTION\s*$")
END = re.compile(r"^\s*#+\s*END SOLUTION\s*$")
#: What replaces a marked block: a statement, so that a function body or a loop stays valid Python,
#: and no exception (nbgrader's own stub raises NotImplementedError, a traceback for the student).
CODE_STUB = "...  # YOUR CODE HERE"
MARKDOWN_STUB = "YOUR ANSWER HERE"
#: What the checks of ``ifslib.exercises`` print: "name: correct." or "name: not yet. Hint: ...".
CORRECT = re.compile(r": correct\.\s*$", re.M)
NOT_YET = re.compile(r": not yet\.")


class MarkerError(ValueError):
    """Solution markers that do not pair up."""


@dataclass
class Piece:
    """A run of a cell's lines: shown to the student (``solution`` False) or a marked solution."""

    text: str
    solution: bool = False
    indent: str = ""


def split(source: str) -> list[Piece]:
    """The cell's source as alternating shown and solution pieces, the marker lines dropped.

    Raises `MarkerError` (with the 1-based line) on a BEGIN inside a block, an END outside one, or a
    block never closed.
    """
    pieces, lines, begun = [], [], None
    for number, line in enumerate(source.splitlines(keepends=True), 1):
        opening, closing = BEGIN.match(line.rstrip("\n")), END.match(line.rstrip("\n"))
        if opening and begun is not None:
            raise MarkerError(f"line {number}: BEGIN SOLUTION inside the block opened at line {begun[0]}")
        if closing and begun is None:
            raise MarkerError(f"line {number}: END SOLUTION without BEGIN SOLUTION")
        if opening:
            pieces.append(Piece("".join(lines)))
            lines, begun = [], (number, opening["indent"])
        elif closing:
            pieces.append(Piece("".join(lines), True, begun[1]))
            lines, begun = [], None
        else:
            lines.append(line)
    if begun is not None:
        raise MarkerError(f"line {begun[0]}: BEGIN SOLUTION without END SOLUTION")
    pieces.append(Piece("".join(lines)))
    return [p for p in pieces if p.text or p.solution]


def has_solution(cell) -> bool:
    return any(BEGIN.match(line) for line in cell.source.splitlines())


def is_exercise(cell) -> bool:
    """A cell the student answers: tagged ``exercise``, nbgrader's answer cell, or one with a marked solution."""
    grader = cell.metadata.get("nbgrader", {})
    return "exercise" in cell.metadata.get("tags", []) or bool(grader.get("solution")) or has_solution(cell)


def has_exercise(book) -> bool:
    return any(is_exercise(cell) for cell in book.cells)


def student_source(source: str, stub: str = CODE_STUB) -> str:
    """``source`` with each marked block replaced by ``stub`` at the block's indentation."""
    pieces = split(source)
    if not any(piece.solution for piece in pieces):
        return source
    text = "".join(f"{p.indent}{stub}\n" if p.solution else p.text for p in pieces)
    return text if source.endswith("\n") else text.removesuffix("\n")


def student_notebook(book, name: str = "notebook"):
    """The student edition of ``book`` (a copy): solutions stubbed, outputs and counts cleared.

    Raises `MarkerError` naming ``name`` and the cell (its index and id) for unbalanced markers.
    """
    book = copy.deepcopy(book)
    for index, cell in enumerate(book.cells):
        try:
            if cell.cell_type == "code":
                cell.source = student_source(cell.source)
                cell.outputs = []
                cell.execution_count = None
                cell.metadata.pop("execution", None)  # nbclient's timings of the instructor's run
            elif cell.cell_type == "markdown":
                cell.source = student_source(cell.source, MARKDOWN_STUB)
        except MarkerError as error:
            raise MarkerError(f"{name}, cell {index} (id {cell.get('id', '?')}): {error}") from None
    return book


def solution_lines(book) -> set[str]:
    """The instructor's marked lines (stripped, non-blank) that occur nowhere outside a marked block."""
    inside, outside = set(), set()
    for cell in book.cells:
        for piece in split(cell.source):
            lines = {line.strip() for line in piece.text.splitlines() if line.strip()}
            (inside if piece.solution else outside).update(lines)
    return inside - outside


def surviving_solutions(instructor, student) -> list[str]:
    """Solution lines of ``instructor`` still present in ``student``'s cells."""
    solutions = solution_lines(instructor)
    found = {line.strip() for cell in student.cells for line in cell.source.splitlines()}
    return sorted(solutions & found)


#: What a notebook that runs the exercises' checks but marks no exercise is, in the student edition.
UNMARKED = ("calls ifslib.exercises but has no exercise cell (no marked solution, no 'exercise' tag): "
            "copied as it is, with any worked answer in it")


def calls_checks(book) -> bool:
    return any("ifslib.exercises.check_" in c.source for c in book.cells if c.cell_type == "code")


def write_edition(out: Path, source: Path = NOTEBOOKS) -> list[Path]:
    """Write the student edition into ``out``; returns the rewritten notebooks (those with an exercise).

    Every notebook is transformed before anything is written, so unbalanced markers leave ``out`` as it was.
    """
    editions, copies = {}, []
    for path in sorted(source.glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        if has_exercise(book):
            editions[path.name] = student_notebook(book, path.name)
        else:
            copies.append(path)
            if calls_checks(book):
                print(f"warning: {path.name} {UNMARKED}", file=sys.stderr)
    out.mkdir(parents=True, exist_ok=True)
    for name, book in editions.items():
        nbformat.validate(book)
        nbformat.write(book, out / name)
    for path in copies:
        shutil.copy2(path, out / path.name)
    print(f"student edition in {_shown(out)}: {len(editions)} with exercises "
          f"({', '.join(editions) or 'none'}), {len(copies)} copied as they are")
    return [out / name for name in editions]


def _shown(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def _text(cell) -> str:
    """What a code cell printed: its streams and the plain text of its results."""
    parts = []
    for output in cell.get("outputs", []):
        if output.output_type == "stream":
            parts.append(output.text)
        elif output.output_type in ("execute_result", "display_data"):
            parts.append(output.get("data", {}).get("text/plain", ""))
    return "".join(parts)


def check_notebook(path: Path, instructor_path: Path, timeout: int = 600) -> tuple[list[str], float, int]:
    """Execute the student notebook ``path`` in a temporary copy; returns (problems, seconds, exercises)."""
    from nbclient import NotebookClient

    student = nbformat.read(path, as_version=4)
    instructor = nbformat.read(instructor_path, as_version=4)
    problems = [f"solution line left in: {line!r}" for line in surviving_solutions(instructor, student)]
    stored = [i for i, c in enumerate(student.cells) if c.cell_type == "code" and (c.outputs or c.execution_count)]
    if stored:
        problems.append(f"cells {stored} hold outputs or execution counts")
    exercises = [i for i, c in enumerate(student.cells) if c.cell_type == "code" and is_exercise(c)]
    with tempfile.TemporaryDirectory(prefix="student-") as folder:
        copy_path = Path(folder) / path.name
        shutil.copy2(path, copy_path)
        book = nbformat.read(copy_path, as_version=4)
        started = time.perf_counter()
        NotebookClient(book, timeout=timeout, kernel_name="python3", allow_errors=True,
                       resources={"metadata": {"path": folder}}).execute()
        seconds = time.perf_counter() - started
    for index, cell in enumerate(book.cells):
        if cell.cell_type != "code":
            continue
        for output in cell.outputs:
            if output.output_type == "error":
                problems.append(f"cell {index} raised {output.ename}: {output.evalue}")
        text = _text(cell)
        right = [line for line in text.splitlines() if CORRECT.search(line)]
        if right:
            problems.append(f"cell {index} printed {right[0][:100]!r} with no answer written")
        if index in exercises and not NOT_YET.search(text):
            problems.append(f"exercise cell {index} printed no 'not yet'")
    return problems, seconds, len(exercises)


def check(editions: list[Path], source: Path = NOTEBOOKS, timeout: int = 600) -> int:
    """Execute and check each rewritten notebook; prints one line each, returns the number that failed."""
    os.environ["IFSLIB_THREADS"] = "1"  # the kernels inherit the environment
    os.environ.pop("MPLBACKEND", None)  # the student's inline backend
    failed = 0
    for path in editions:
        problems, seconds, count = check_notebook(path, source / path.name, timeout)
        if problems:
            failed += 1
            print(f"{path.name}: FAILED in {seconds:.0f} s", flush=True)
            for problem in problems:
                print(f"    {problem}", flush=True)
        else:
            cells = f"{count} exercise cell" + ("s, each" if count != 1 else ",")
            print(f"{path.name}: ran in {seconds:.0f} s, no error; {cells} 'not yet'; no solution line left",
                  flush=True)
    return failed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=DEFAULT_OUT, help="folder (default build/student)")
    parser.add_argument("--check", action="store_true", help="then execute each rewritten notebook and check it")
    parser.add_argument("--source", type=Path, default=NOTEBOOKS,
                        help="the instructor's notebooks (default notebooks/)")
    parser.add_argument("--timeout", type=int, default=600, help="seconds a cell may run in --check")
    args = parser.parse_args(argv)
    try:
        editions = write_edition(args.out, args.source)
    except MarkerError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if not args.check:
        return 0
    started = time.perf_counter()
    failed = check(editions, args.source, args.timeout)
    # a notebook that checks answers but marks none would hand its worked answers to the students
    unmarked = [p.name for p in sorted(args.source.glob("*.ipynb"))
                if (args.out / p.name) not in editions and calls_checks(nbformat.read(p, as_version=4))]
    for name in unmarked:
        print(f"{name}: FAILED: {UNMARKED}", flush=True)
    print(f"student edition checked: {len(editions) - failed} of {len(editions)} with exercises passed in "
          f"{time.perf_counter() - started:.0f} s" + (f"; {len(unmarked)} unmarked" if unmarked else ""))
    return 1 if failed or unmarked else 0


if __name__ == "__main__":
    sys.exit(main())
