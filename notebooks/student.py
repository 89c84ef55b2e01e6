"""Write the student edition of the notebooks: ``python notebooks/student.py [OUT] [--check]``.

The notebooks in ``notebooks/`` are the instructor's edition. Each exercise is nbgrader's pair: an
answer cell holding the worked answer between ``### BEGIN SOLUTION`` / ``### END SOLUTION`` (at the
indentation of the code it belongs to), and a locked test cell whose further tests sit between
``### BEGIN HIDDEN TESTS`` / ``### END HIDDEN TESTS``; a written answer is a markdown answer cell
with a model answer and a rubric between the solution markers.

The student edition (``OUT``, default ``build/student/``) is nbgrader's own release: the notebooks
with nbgrader cells are laid out as the course's assignment and ``nbgrader generate_assignment``
writes them (``course/grading.py``, with ``course/nbgrader_config.py``): each solution block becomes
``...  # YOUR CODE HERE`` (a written one ``YOUR ANSWER HERE``), hidden tests are removed, outputs
cleared and the test cells locked. The other notebooks are copied as they are, stored outputs
included (they hold no solution, and the student gets the whole course in one folder). Markers that do not pair up are refused before anything is
written, naming the notebook and the cell.

``--check`` then executes each released notebook top to bottom at its quick values (nbclient, a fresh python3 kernel, a
temporary folder, ``IFSLIB_THREADS=1``) and fails unless every test cell raises ``AssertionError``
(nothing is answered yet) and no other cell raises, and no solution or hidden-test line of the
instructor's edition is left. It also fails on a notebook that runs the exercises' harness
(``ifslib.exercises.run_answer``) but has no nbgrader cell: copied as it is, it would give its
answers away. Needs nbgrader (``pip install -e '.[grading]'``).

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
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
sys.path.insert(0, str(ROOT / "course"))
from run_edition import execute, is_test  # noqa: E402  the check runs each notebook as CI runs the student edition
DEFAULT_OUT = ROOT / "build" / "student"

#: nbgrader's delimiters: a comment line (any number of comment characters) holding only the words.
BEGIN = re.compile(r"^(?P<indent>\s*)#+\s*BEGIN SOLUTION\s*$")
END = re.compile(r"^\s*#+\s*END SOLUTION\s*$")
#: What replaces a marked block: a statement, so that a function body or a loop stays valid Python,
#: and no exception (nbgrader's own stub raises NotImplementedError, a traceback for the student).
CODE_STUB = "...  # YOUR CODE HERE"
MARKDOWN_STUB = "YOUR ANSWER HERE"
#: nbgrader's markers of the tests a student does not see.
HIDDEN = re.compile(r"^[ \t]*#+\s*BEGIN HIDDEN TESTS.*?#+\s*END HIDDEN TESTS[ \t]*$", re.M | re.S)


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


def hidden_lines(book) -> set[str]:
    """The lines (stripped, non-blank) of the instructor's hidden tests that occur nowhere else."""
    inside, outside = set(), set()
    for cell in book.cells:
        hidden = "".join(m.group(0) for m in HIDDEN.finditer(cell.source))
        inside.update(line.strip() for line in hidden.splitlines() if line.strip())
        outside.update(line.strip() for line in HIDDEN.sub("", cell.source).splitlines() if line.strip())
    return inside - outside - {"### BEGIN HIDDEN TESTS", "### END HIDDEN TESTS"}


#: What a notebook that runs the exercises' harness but has no nbgrader cell is, in the student edition.
UNMARKED = ("runs ifslib.exercises but has no nbgrader cell (no answer cell, no test cell): "
            "copied as it is, with any worked answer in it")


def calls_checks(book) -> bool:
    return any("ifslib.exercises.run_answer" in c.source for c in book.cells if c.cell_type == "code")


def _grading():
    """``course/grading.py``, which lays the course out and runs nbgrader."""
    from scripts import load_script  # course/scripts.py, on sys.path above

    return load_script("course/grading.py", "ifslib_course_grading")


def write_edition(out: Path, source: Path = NOTEBOOKS) -> list[Path]:
    """Write the student edition into ``out``; returns the released notebooks (those with nbgrader cells).

    Every notebook's markers are checked before anything is written, so unbalanced markers leave ``out``
    as it was.
    """
    released, copies = [], []
    for path in sorted(source.glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        student_notebook(book, path.name)   # raises MarkerError for markers that do not pair up
        if has_exercise(book):
            released.append(path.name)
        else:
            copies.append(path)
            if calls_checks(book):
                print(f"warning: {path.name} {UNMARKED}", file=sys.stderr)
    out.mkdir(parents=True, exist_ok=True)
    if released:
        grading = _grading()
        with tempfile.TemporaryDirectory(prefix="course-") as folder:
            grading.layout(Path(folder) / "course", source)
            release = grading.generate(Path(folder) / "course")
            for name in released:   # one folder an assignment (a lecture)
                shutil.copy2(next(release.glob(f"*/{name}")), out / name)
    for path in copies:
        shutil.copy2(path, out / path.name)
    print(f"student edition in {_shown(out)} (nbgrader's release): {len(released)} with exercises "
          f"({', '.join(released) or 'none'}), {len(copies)} copied as they are")
    return [out / name for name in released]


def _shown(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def check_notebook(path: Path, instructor_path: Path, timeout: int = 600) -> tuple[list[str], float, int]:
    """Execute the released notebook ``path`` in a temporary folder; returns (problems, seconds, test cells)."""
    student = nbformat.read(path, as_version=4)
    instructor = nbformat.read(instructor_path, as_version=4)
    problems = [f"solution line left in: {line!r}" for line in surviving_solutions(instructor, student)]
    text = {line.strip() for cell in student.cells for line in cell.source.splitlines()}
    problems += [f"hidden test line left in: {line!r}" for line in sorted(hidden_lines(instructor) & text)]
    stored = [i for i, c in enumerate(student.cells) if c.cell_type == "code" and (c.outputs or c.execution_count)]
    if stored:
        problems.append(f"cells {stored} hold outputs or execution counts")
    with tempfile.TemporaryDirectory(prefix="student-") as folder:
        book, seconds = execute(Path(shutil.copy2(path, Path(folder) / path.name)), timeout)
    tests = 0
    for index, cell in enumerate(book.cells):
        if cell.cell_type != "code":
            continue
        errors = [o for o in cell.outputs if o.output_type == "error"]
        if is_test(cell):
            tests += 1
            if not any(e.ename == "AssertionError" and e.evalue for e in errors):
                got = f"{errors[0].ename}: {errors[0].evalue}" if errors else "nothing"
                problems.append(f"test cell {index} raised {got}, not an AssertionError with a hint")
        else:
            problems += [f"cell {index} raised {e.ename}: {e.evalue}" for e in errors]
    return problems, seconds, tests


def check(editions: list[Path], source: Path = NOTEBOOKS, timeout: int = 600) -> int:
    """Execute and check each released notebook, one per core at a time (one thread each); prints one line each,
    returns the number that failed."""
    os.environ["IFSLIB_THREADS"] = "1"  # the kernels inherit the environment
    os.environ.pop("MPLBACKEND", None)  # the student's inline backend
    failed = 0
    with ThreadPoolExecutor(len(os.sched_getaffinity(0))) as pool:  # each notebook's work is in its kernel
        runs = pool.map(lambda path: check_notebook(path, source / path.name, timeout), editions)
        for path, (problems, seconds, count) in zip(editions, runs):
            if problems:
                failed += 1
                print(f"{path.name}: FAILED in {seconds:.0f} s", flush=True)
                for problem in problems:
                    print(f"    {problem}", flush=True)
            else:
                print(f"{path.name}: ran in {seconds:.0f} s; each of its {count} test cells raised AssertionError "
                      "(nothing answered), no other cell raised; no solution or hidden test left", flush=True)
    return failed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", type=Path, default=DEFAULT_OUT, help="folder (default build/student)")
    parser.add_argument("--check", action="store_true", help="then execute each released notebook and check it")
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
    # a notebook that runs the harness but has no nbgrader cell would hand its worked answers to the students
    unmarked = [p.name for p in sorted(args.source.glob("*.ipynb"))
                if (args.out / p.name) not in editions and calls_checks(nbformat.read(p, as_version=4))]
    for name in unmarked:
        print(f"{name}: FAILED: {UNMARKED}", flush=True)
    print(f"student edition checked: {len(editions) - failed} of {len(editions)} with exercises passed in "
          f"{time.perf_counter() - started:.0f} s" + (f"; {len(unmarked)} unmarked" if unmarked else ""))
    return 1 if failed or unmarked else 0


if __name__ == "__main__":
    sys.exit(main())
