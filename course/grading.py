"""A course of this project's notebooks under nbgrader: lay it out, release it, autograde submissions.

    python course/grading.py build/course            # lay out build/course, generate the release
    python course/grading.py build/course --check    # then autograde the instructor's source and the blank
                                                     # release, and fail unless they score full and 0

One assignment per lecture (``lecture1`` ... ``lecture7``, the decks of ``docs/slides/lectures.yaml``;
a notebook taught over two lectures is due with the later one), so that each can be due the week of
its lecture. Each graded notebook is at its teaching values with a locked grading cell after its
parameters cell (``grading_run.py``): while nbgrader executes it (autograde, Validate) the lesson runs
at its grading sizes and skips the demonstrations no check needs; every other code cell of the lesson
is locked, so nbgrader restores it before it grades. ``nbgrader_checks.py`` reads each submission's
own cells before they run and gives 0 to the tests they could fool, and keeps the hidden tests out of
the feedback. ``--quick`` also injects each notebook's quick values (``metadata["ifslib"]["quick"]``).
``--check`` first makes sure the paper's images can be found, then submits four students:
``instructor`` (the source, solved: every auto-graded point, no tamper alarm, nothing untrusted),
``blank`` (the release, unanswered: 0), ``lazy`` (``lazy_submission.py``: 0) and ``tricks``
(``tricks_submission.py``: under half), autogrades them with nbgrader itself, prints each one's points,
the cells left for manual grading and how long its autograde took, and checks that the feedback
``nbgrader generate_feedback`` writes holds no line of a hidden test.
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
from grading_run import parameters_index, with_grading_cell  # noqa: E402
from run_edition import with_quick_values  # noqa: E402  one way to inject the quick values, here and there
from scripts import load_script  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
CONFIG = Path(__file__).resolve().parent / "nbgrader_config.py"
CHECKS = [Path(__file__).resolve().parent / name for name in ("nbgrader_checks.py", "notebook_scan.py")]
LECTURES = ROOT / "docs" / "slides" / "lectures.yaml"


def lecture_of() -> dict[str, str]:
    """notebook name -> the assignment it belongs to: the last lecture whose deck holds it (the tutorial,
    taught over lectures 1 and 2, is due with lecture 2), from ``docs/slides/lectures.yaml``."""
    import yaml

    out = {}
    for deck in yaml.safe_load(LECTURES.read_text()):
        for part in deck["parts"]:
            out[part["notebook"]] = deck["deck"]
    return out


def is_graded(book) -> bool:
    """Whether a notebook has nbgrader cells (an answer or a test)."""
    return any(cell.metadata.get("nbgrader") for cell in book.cells)


def layout(course: Path, source: Path = NOTEBOOKS, quick: bool = False) -> dict[str, list[str]]:
    """Write ``course/nbgrader_config.py`` and ``course/source/<lecture>/`` (the graded notebooks, one
    assignment per lecture: `lecture_of`); returns assignment -> its notebooks' names."""
    if course.exists():
        shutil.rmtree(course)
    (course / "source").mkdir(parents=True)
    shutil.copy2(CONFIG, course / "nbgrader_config.py")
    for checks in CHECKS:
        shutil.copy2(checks, course / checks.name)
    lectures = lecture_of()
    names: dict[str, list[str]] = {}
    for path in sorted(source.glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        if is_graded(book):
            # a graded notebook without a parameters cell gets no grading cell (it has nothing to shrink)
            teaching = ({} if parameters_index(book) is None else
                        load_script("notebooks/run.py", "ifslib_notebooks_run").teaching_parameters(path))
            book = lock_lesson(with_grading_cell(with_quick_values(book) if quick else book, path.stem, teaching),
                               path.stem)
            assignment = lectures.get(path.stem)
            if assignment is None:
                raise SystemExit(f"{path.name} has exercises but no lecture in {LECTURES.relative_to(ROOT)}")
            (course / "source" / assignment).mkdir(exist_ok=True)
            nbformat.write(book, course / "source" / assignment / path.name)
            names.setdefault(assignment, []).append(path.stem)
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
    from ifslib import data
    from ifslib.errors import IFSError

    missing = []
    for name in data.NAMES:   # each one found, or downloaded into the cache now
        try:
            data.path(name, timeout=10.0)
        except IFSError:
            missing.append(f"{name}.png")
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
    """``nbgrader generate_assignment`` of every assignment laid out: the release folder, one folder an
    assignment (solutions and hidden tests removed)."""
    for folder in sorted((course / "source").iterdir()):
        nbgrader(course, "generate_assignment", folder.name)
    return course / "release"


@dataclass(frozen=True)
class Score:
    """One student's autograded assignment: the tests' points, and the written answers."""

    student: str
    auto: float          # points the test cells gave
    auto_max: float
    seconds: float       # nbgrader autograde's time, every assignment in one call
    written: int         # written answer cells (markdown, graded by a person)
    manual_cells: int    # of them, those nbgrader left for manual grading (an unchanged one gets 0 at once)
    alarms: int = 0      # nbgrader's tamper alarms ("Attribute ... has changed") in its autograde
    not_trusted: int = 0  # findings of nbgrader_checks.ScanCells (constructs that change the checks)

    def line(self) -> str:
        return (f"{self.student}: auto points {self.auto:g} of {self.auto_max:g} in {self.seconds:.0f} s, "
                f"manual cells {self.manual_cells} of {self.written} written answers, "
                f"{self.alarms} tamper alarms, {self.not_trusted} untrusted constructs")


def autograde(course: Path, submissions: dict[str, Path]) -> list[Score]:
    """Submit each folder (one subfolder an assignment) as a student, run ``nbgrader autograde`` on each
    assignment, print its time, and read the gradebook."""
    from nbgrader.api import Gradebook

    logs, seconds = {}, {}
    for student, folder in submissions.items():
        for assignment in sorted(p.name for p in folder.iterdir() if p.is_dir()):
            shutil.copytree(folder / assignment, course / "submitted" / student / assignment, dirs_exist_ok=True)
        # every assignment of the course in one call, as the page grades a student's whole course: nbgrader
        # starts once (about 2.5 s a call) rather than once an assignment
        started = time.perf_counter()
        logs[student] = nbgrader(course, "autograde", "*", "--student", student, "--create")
        seconds[student] = time.perf_counter() - started
        print(f"  autograded {student}'s whole course in {seconds[student]:.0f} s", flush=True)
    scores = []
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as book:
        for student in submissions:
            grades = [grade for assignment in book.assignments for notebook in
                      book.find_submission(assignment.name, student).notebooks for grade in notebook.grades]
            tests = [g for g in grades if g.cell_type == "code"]
            written = [g for g in grades if g.cell_type == "markdown"]
            scores.append(Score(student, sum(g.auto_score or 0 for g in tests), sum(g.max_score for g in tests),
                                seconds[student], len(written), sum(bool(g.needs_manual_grade) for g in written),
                                logs[student].count("has changed!"), logs[student].count("untrusted:")))
            failed = [g.name for g in tests if (g.auto_score or 0) < g.max_score]
            if failed and student == "instructor":
                print(f"  {student}: tests that failed: {', '.join(failed)}", flush=True)
    return scores


def feedback_leaks(course: Path, student: str) -> list[str]:
    """``nbgrader generate_feedback`` for ``student``; the lines of its HTML that only a hidden test holds."""
    import html
    import re

    # each notebook's hidden-test lines found nowhere else in it (not "assert np.allclose("): the student
    # edition's own reading of the markers
    hidden_lines = load_script("notebooks/student.py", "ifslib_student_edition").hidden_lines
    hidden = {path.stem: hidden_lines(nbformat.read(path, as_version=4))
              for path in (course / "source").glob("*/*.ipynb")}
    leaks = []
    nbgrader(course, "generate_feedback", "*", "--student", student)
    for page in (course / "feedback" / student).glob("*/*.html"):
        text = html.unescape(re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8")))
        shown = {line.strip() for line in text.splitlines()}
        leaks += [f"{page.name}: {line}" for line in sorted(hidden.get(page.stem, set()) & shown)]
    return leaks


def check(course: Path, names: dict[str, list[str]]) -> int:
    """Autograde the solved source, the blank release, a lazy submission (``lazy_submission.py``) and one
    of tricks (``tricks_submission.py``); 0 when they score full, 0, 0 and under half of the auto-graded
    points, else 1."""
    from lazy_submission import passed_tests, write_lazy
    from tricks_submission import write_tricks

    release = course / "release"
    for assignment in names:
        write_lazy(release / assignment, course / "lazy" / assignment)
        write_tricks(release / assignment, course / "tricks" / assignment)
    scores = autograde(course, {"instructor": course / "source", "blank": release, "lazy": course / "lazy",
                                "tricks": course / "tricks"})
    for score in scores:
        print(score.line(), flush=True)
    for student in ("lazy", "tricks"):
        walked = [t for a in names for t in passed_tests(course / "gradebook.db", a, student)]
        print(f"  {student}: the tests it passed ({len(walked)}): {', '.join(walked) or 'none'}", flush=True)
    leaks = feedback_leaks(course, "tricks")
    print(f"  feedback: {len(leaks)} lines of hidden tests in the tricks student's HTML", flush=True)
    instructor, blank, lazy, tricks = scores
    problems = [problem for failed, problem in [
        (instructor.auto != instructor.auto_max or instructor.auto_max == 0,
         "the instructor's source does not get every auto-graded point"),
        (instructor.manual_cells != instructor.written,
         "a written answer of the instructor's source was not left for manual grading"),
        (blank.auto != 0, "the blank release gets auto-graded points"),
        (lazy.auto != 0, f"the lazy submission gets {lazy.auto:g} of {lazy.auto_max:g} auto-graded points, not 0"),
        (tricks.auto >= tricks.auto_max / 2,
         f"the submission of tricks gets {tricks.auto:g} of {tricks.auto_max:g} auto-graded points, not under half"),
        (instructor.alarms or blank.alarms, "nbgrader raised a tamper alarm on a submission that changed no locked cell"),
        (instructor.not_trusted, "the instructor's source has constructs the checks do not trust"),
        (leaks, f"the feedback shows hidden tests: {leaks[:3]}"),
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
                        help="autograde the source (full), the release (0), a lazy submission (0) and one of tricks (under half)")
    args = parser.parse_args(argv)
    check_images()
    names = layout(args.course, args.source, args.quick)
    release = generate(args.course)
    for assignment, books in names.items():
        print(f"released {assignment}: {', '.join(books)} in {release / assignment}", flush=True)
    return check(args.course, names) if args.check else 0


if __name__ == "__main__":
    sys.exit(main())
