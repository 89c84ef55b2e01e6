"""A course of this project's notebooks under nbgrader: lay it out, release it, autograde submissions.

    python course/grading.py build/course            # lay out build/course, generate the release
    python course/grading.py build/course --check    # then autograde the instructor's source and the blank
                                                     # release, and fail unless they score full and 0

The assignment ``ifs`` holds every notebook of ``notebooks/`` with nbgrader cells (every lesson
but the explorer and the glossary), each at its teaching values with a locked grading cell after its
parameters cell (``grading_run.py``): while nbgrader executes it (autograde, Validate) the lesson runs
at its grading sizes and skips the demonstrations no check needs. ``--quick`` also injects each
notebook's quick values (``metadata["ifslib"]["quick"]``) after its parameters cell. ``--check`` submits
three students: ``instructor`` (the source, solved: every auto-graded point), ``blank`` (the release,
unanswered: 0) and ``lazy`` (the release answered the laziest way, ``lazy_submission.py``: under half),
autogrades them with nbgrader itself and prints each one's auto-graded points, the cells left for
manual grading (the written answers) and how long its autograde took.
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import nbformat

from ifslib.paths import load_script

sys.path.insert(0, str(Path(__file__).resolve().parent))
from grading_run import parameters_index, with_grading_cell  # noqa: E402
from run_edition import with_quick_values  # noqa: E402  one way to inject the quick values, here and there

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
CONFIG = Path(__file__).resolve().parent / "nbgrader_config.py"
CHECKS = Path(__file__).resolve().parent / "nbgrader_checks.py"
ASSIGNMENT = "ifs"


def is_graded(book) -> bool:
    """Whether a notebook has nbgrader cells (an answer or a test)."""
    return any(cell.metadata.get("nbgrader") for cell in book.cells)


def layout(course: Path, source: Path = NOTEBOOKS, quick: bool = False) -> list[str]:
    """Write ``course/nbgrader_config.py`` and ``course/source/ifs/`` (the graded notebooks); returns their names."""
    if course.exists():
        shutil.rmtree(course)
    folder = course / "source" / ASSIGNMENT
    folder.mkdir(parents=True)
    shutil.copy2(CONFIG, course / "nbgrader_config.py")
    shutil.copy2(CHECKS, course / "nbgrader_checks.py")
    names = []
    for path in sorted(source.glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        if is_graded(book):
            # a graded notebook without a parameters cell gets no grading cell (it has nothing to shrink)
            teaching = ({} if parameters_index(book) is None else
                        load_script("notebooks/run.py", "ifslib_notebooks_run").teaching_parameters(path))
            book = lock_lesson(with_grading_cell(with_quick_values(book) if quick else book, path.stem, teaching),
                               path.stem)
            nbformat.write(book, folder / path.name)
            names.append(path.stem)
    if not names:
        raise SystemExit(f"no notebook in {source} has nbgrader cells")
    return names


def lock_lesson(book, name: str):
    """``book`` with every code cell that is not an answer locked (nbgrader restores a locked cell from
    the source before it grades): the lesson's values and helpers a test reads are the instructor's,
    whatever a submission did to them. Returns ``book``, changed in place."""
    for k, cell in enumerate(book.cells):
        if cell.cell_type == "code" and not cell.metadata.get("nbgrader"):
            cell.metadata["nbgrader"] = {"grade": False, "solution": False, "locked": True,
                                         "grade_id": f"{name}-lesson-{k}", "schema_version": 3}
    return book


def check_images() -> None:
    """Refuse to grade when the paper's target images cannot be found: correct work would score 0."""
    from ifslib.data import missing_images

    missing = missing_images()
    if missing:
        raise SystemExit(
            f"the paper's target images are not found ({', '.join(missing)}): notebooks 02 and 04 read them, "
            "and every submission would lose their points. Set IFSLIB_DATA to a folder holding koch.png, "
            "sierpinski.png, apple.png and flower.png (docs/guide/course.md#grading says where to get them), "
            "or connect this machine to the network once so that ifslib downloads them, then grade again.")


def nbgrader(course: Path, *args: str) -> str:
    """Run the ``nbgrader`` command of this Python's environment in ``course``; raise on failure, else its log."""
    bin_folder = Path(sys.executable).parent
    command = [str(bin_folder / "nbgrader"), *args, "--force"]
    # nbgrader runs alembic (its database migrations) by name: this environment's, first on the PATH
    env = dict(os.environ, PATH=f"{bin_folder}{os.pathsep}{os.environ.get('PATH', '')}")
    done = subprocess.run(command, cwd=course, capture_output=True, text=True, env=env)
    if done.returncode:
        raise SystemExit(f"{' '.join(command[1:])} failed in {course}:\n{done.stdout}\n{done.stderr}")
    return done.stdout + done.stderr


def generate(course: Path) -> Path:
    """``nbgrader generate_assignment``: the release folder (solutions and hidden tests removed)."""
    nbgrader(course, "generate_assignment", ASSIGNMENT)
    return course / "release" / ASSIGNMENT


@dataclass(frozen=True)
class Score:
    """One student's autograded assignment: the tests' points, and the written answers."""

    student: str
    auto: float          # points the test cells gave
    auto_max: float
    written: int         # written answer cells (markdown, graded by a person)
    manual_cells: int    # of them, those nbgrader left for manual grading (an unchanged one gets 0 at once)
    alarms: int = 0      # nbgrader's tamper alarms ("Attribute ... has changed") in its autograde
    not_trusted: int = 0  # findings of nbgrader_checks.ScanCells (constructs that change the checks)

    def line(self) -> str:
        return (f"{self.student}: auto points {self.auto:g} of {self.auto_max:g}, "
                f"manual cells {self.manual_cells} of {self.written} written answers, "
                f"{self.alarms} tamper alarms, {self.not_trusted} untrusted constructs")


def autograde(course: Path, submissions: dict[str, Path]) -> list[Score]:
    """Submit each folder as a student, run ``nbgrader autograde`` and read the gradebook."""
    logs = {}
    for student, folder in submissions.items():
        target = course / "submitted" / student / ASSIGNMENT
        shutil.copytree(folder, target, dirs_exist_ok=True)
        started = time.perf_counter()
        logs[student] = nbgrader(course, "autograde", ASSIGNMENT, "--student", student, "--create")
        print(f"  autograded {student} in {time.perf_counter() - started:.0f} s", flush=True)
    from nbgrader.api import Gradebook

    scores = []
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as book:
        for student in submissions:
            grades = [grade for notebook in book.find_submission(ASSIGNMENT, student).notebooks
                      for grade in notebook.grades]
            tests = [g for g in grades if g.cell_type == "code"]
            written = [g for g in grades if g.cell_type == "markdown"]
            scores.append(Score(student, sum(g.auto_score or 0 for g in tests), sum(g.max_score for g in tests),
                                len(written), sum(bool(g.needs_manual_grade) for g in written),
                                logs[student].count("has changed!"), logs[student].count("untrusted:")))
            failed = [g.name for g in tests if (g.auto_score or 0) < g.max_score]
            if failed and student == "instructor":
                print(f"  {student}: tests that failed: {', '.join(failed)}", flush=True)
    return scores


def check(course: Path, names: list[str]) -> int:
    """Autograde the solved source, the blank release and a lazy submission (``lazy_submission.py``);
    0 when they score full, 0 and under half of the auto-graded points, else 1."""
    from lazy_submission import passed_tests, write_lazy
    from tricks_submission import write_tricks

    release, lazy_folder = course / "release" / ASSIGNMENT, course / "lazy" / ASSIGNMENT
    tricks_folder = course / "tricks" / ASSIGNMENT
    write_lazy(release, lazy_folder)
    write_tricks(release, tricks_folder)
    scores = autograde(course, {"instructor": course / "source" / ASSIGNMENT, "blank": release, "lazy": lazy_folder,
                                "tricks": tricks_folder})
    for score in scores:
        print(score.line(), flush=True)
    for student in ("lazy", "tricks"):
        walked = passed_tests(course / "gradebook.db", ASSIGNMENT, student)
        print(f"  {student}: the tests it passed ({len(walked)}): {', '.join(walked) or 'none'}", flush=True)
    instructor, blank, lazy, tricks = scores
    problems = [problem for failed, problem in [
        (instructor.auto != instructor.auto_max or instructor.auto_max == 0,
         "the instructor's source does not get every auto-graded point"),
        (instructor.manual_cells != instructor.written,
         "a written answer of the instructor's source was not left for manual grading"),
        (blank.auto != 0, "the blank release gets auto-graded points"),
        (lazy.auto >= lazy.auto_max / 2,
         f"the lazy submission gets {lazy.auto:g} of {lazy.auto_max:g} auto-graded points, not under half"),
        (tricks.auto >= tricks.auto_max / 2,
         f"the submission of tricks gets {tricks.auto:g} of {tricks.auto_max:g} auto-graded points, not under half"),
        (instructor.alarms or blank.alarms, "nbgrader raised a tamper alarm on a submission that changed no locked cell"),
        (instructor.not_trusted, "the instructor's source has constructs the checks do not trust"),
    ] if failed]
    for problem in problems:
        print(f"FAILED: {problem}", flush=True)
    return 1 if problems else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("course", type=Path, help="the course folder to write (replaced)")
    parser.add_argument("--source", type=Path, default=NOTEBOOKS, help="the instructor's notebooks")
    parser.add_argument("--quick", action="store_true", help="inject each notebook's quick values (CI)")
    parser.add_argument("--check", action="store_true",
                        help="autograde the source (full), the release (0) and a lazy submission (under half)")
    args = parser.parse_args(argv)
    check_images()
    names = layout(args.course, args.source, args.quick)
    release = generate(args.course)
    print(f"released {', '.join(names)} in {release}", flush=True)
    return check(args.course, names) if args.check else 0


if __name__ == "__main__":
    sys.exit(main())
