"""The course page's commands and the exercises it assigns, checked against the project as it is.

Every shell command in ``docs/guide/course.md`` (an inline code span or a fenced line that starts
with ``make``, ``python``, ``papermill`` or a ``.venv/bin/`` program) is checked without running
anything long: a make target must exist and ``make -n`` must accept it; a Python script or module
must accept each of the command's options (read from its ``--help``); a papermill command must name
a notebook that exists and only parameters its ``parameters`` cell defines. The exercises the page
assigns must exist: each notebook named in an "At home" paragraph has an "On your own" section
with graded cells (nbgrader metadata), the page's table of exercises has a row for each notebook of
each lecture (``docs/slides/lectures.yaml``) with the counts of its nbgrader cells, each "At home"
paragraph counts its lecture's exercises and names as on paper exactly its written ones, and asks
only for what a student has (the student edition, ifslib and JupyterLab: no ``make``, papermill or
checkout), each value it sets in a parameters cell being a parameter of the notebook.
"""
import dataclasses
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest
from common_testing import load_module

pytestmark = pytest.mark.slow  # make test-slow: the course page's commands run in subprocesses


ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "guide" / "course.md"
NOTEBOOKS = ROOT / "notebooks"
PROGRAMS = ("make", "python", "papermill", ".venv/bin/", "../.venv/bin/")
slides = load_module("ifslib_docs_slides", ROOT / "docs" / "slides.py")


def commands(text):
    """The shell commands of a markdown text: code spans and fenced lines that start with a program."""
    spans = re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    fenced = [line for block in re.findall(r"```(?:bash|sh|shell)?\n(.*?)```", text, flags=re.S)
              for line in block.splitlines()]
    found = []
    for candidate in spans + fenced:
        candidate = candidate.split("#")[0].strip()
        # a bare script with arguments is a command too (and a wrong one: it needs its interpreter);
        # a bare file name (`docs/slides.py`) is a reference, not a command
        if candidate.startswith(PROGRAMS) or re.match(r"^[\w./-]+\.py\s+\S", candidate):
            found.append(candidate)
    return found


def test_the_page_has_commands_and_they_are_found():
    found = commands(PAGE.read_text())
    assert any(c.startswith("make ") for c in found) and any("papermill" in c for c in found)


def test_commands_finds_every_kind_and_the_broken_one():
    text = ("Run `make setup`, then `notebooks/run.py --preset paper 02` (`docs/slides.py`) and\n"
            "```bash\npython -m ifslib fit a.png -o a.json  # a fit\n```\nnot `ifslib.fit`.")
    assert commands(text) == ["make setup", "notebooks/run.py --preset paper 02",
                              "python -m ifslib fit a.png -o a.json"]


def _program(word):
    """A command's program, as this checkout runs it: the venv's python for every python."""
    name = word.rsplit("/", 1)[-1]
    return sys.executable if name.startswith("python") else str(Path(sys.executable).parent / name)


def _options_of(help_text):
    """The option strings (``-o``, ``--pattern``) an argparse ``--help`` lists, and whether it takes positionals."""
    options = set(re.findall(r"(?<![\w-])(--?[A-Za-z][\w-]*)", help_text))
    usage = help_text.split("\n\n")[0]
    positionals = bool(re.search(r"\s(?![\[-])[a-z_]+(?:\s|$|\.\.\.)", usage.split(":", 1)[-1]
                                 .replace("usage", "")))
    return options, positionals


def _check_against_help(argv, label):
    """Every option of ``argv`` (a python program and its arguments) is one its ``--help`` lists."""
    run = subprocess.run(argv[:_split(argv)] + ["--help"], capture_output=True, text=True, cwd=ROOT,
                         timeout=120)
    assert run.returncode == 0, f"{label}: --help fails:\n{run.stderr[-800:]}"
    options, _ = _options_of(run.stdout)
    for word in argv[_split(argv):]:
        if word.startswith("-"):
            assert word.split("=")[0] in options, f"{label}: {word} is not an option of it:\n{run.stdout}"


def _split(argv):
    """Where a python command's own arguments start: after ``-m module [subcommand]`` or the script."""
    if argv[1] == "-m":
        return 4 if argv[2] == "ifslib" else 3
    return 2


def _parameters(notebook):
    cell = next(c for c in json.loads(notebook.read_text())["cells"]
                if "parameters" in c["metadata"].get("tags", []))
    return set(re.findall(r"^(\w+)\s*=", "".join(cell["source"]), flags=re.M))


def check(command):
    """Check one command of the page; raises AssertionError saying what is wrong."""
    words = shlex.split(command)
    head = words[0]
    if head == "make":
        makefile = (ROOT / "Makefile").read_text()
        targets = [w for w in words[1:] if "=" not in w]
        for target in targets:
            assert re.search(rf"^{re.escape(target)}\s*:", makefile, flags=re.M), f"{command}: no make target {target}"
        run = subprocess.run(["make", "-n", *words[1:]], capture_output=True, text=True, cwd=ROOT, timeout=60)
        assert run.returncode == 0, f"{command}: make -n fails:\n{run.stderr[-800:]}"
        return
    if head.endswith(".py"):
        raise AssertionError(f"{command}: a script needs its interpreter (.venv/bin/python {head} ...)")
    program = _program(head)
    assert Path(program).exists(), f"{command}: {head} is not installed ({program})"
    if head.endswith("papermill"):
        notebook, options = NOTEBOOKS / words[1], words[3:]
        assert notebook.exists(), f"{command}: no notebook {words[1]} in notebooks/"
        names = _parameters(notebook)
        for flag, name in zip(options, options[1:]):
            if flag in ("-p", "--parameters"):
                assert name in names, f"{command}: {name} is not a parameter of {words[1]} ({sorted(names)})"
        return
    if head.endswith("jupyter"):
        assert (ROOT / words[-1]).exists(), f"{command}: no folder {words[-1]}"
        run = subprocess.run([program, *words[1:-1], "--help"], capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, f"{command}: {' '.join(words[:-1])} --help fails"
        return
    if head.rsplit("/", 1)[-1].startswith("python"):
        script = words[1]
        if script != "-m":
            path = (ROOT / script) if (ROOT / script).exists() else (NOTEBOOKS / script)
            assert path.exists(), f"{command}: no script {script}"
            words = [words[0], str(path), *words[2:]]
        _check_against_help([sys.executable, *words[1:]], command)
        return
    raise AssertionError(f"{command}: no check for the program {head}")


@pytest.mark.parametrize("command", commands(PAGE.read_text()))
def test_each_command_of_the_page_runs(command):
    check(command)


@pytest.mark.parametrize("command, reason", [
    ("notebooks/run.py --preset paper 02", "interpreter"),
    ("make no-such-target", "no make target"),
    (".venv/bin/python -m ifslib fit x.png --no-such-option", "not an option"),
    ("../.venv/bin/papermill 02_fitting_gallery.ipynb o.ipynb -p no_such 1", "not a parameter"),
    ("../.venv/bin/papermill 99_missing.ipynb o.ipynb", "no notebook"),
])
def test_check_refuses_a_broken_command(command, reason):
    with pytest.raises(AssertionError, match=reason):
        check(command)


def graded(notebook):
    """(exercises, of them written) of a notebook, from nbgrader metadata: one graded cell an exercise."""
    cells = json.loads(notebook.read_text())["cells"]
    marks = [(c["cell_type"], c["metadata"]["nbgrader"]) for c in cells if "nbgrader" in c["metadata"]]
    exercises = [kind for kind, meta in marks if meta.get("grade")]
    return len(exercises), sum(kind == "markdown" for kind in exercises)


def assigned(text):
    """The notebooks the page's "At home" paragraphs name (``NN_name``)."""
    homework = re.findall(r"\*\*At home\.\*\*(.*?)(?:\n\n|\Z)", text, flags=re.S)
    return sorted({name for paragraph in homework for name in re.findall(r"\b(\d\d_[a-z_]+)\b", paragraph)
                   if (NOTEBOOKS / f"{name}.ipynb").exists()})


def test_the_page_assigns_the_lessons_exercises():
    names = assigned(PAGE.read_text())
    assert {"02_fitting_gallery", "03_gradient_fields", "04_local_minima", "06_convergence_study",
            "08_real_fractals"} <= set(names)


@pytest.mark.parametrize("name", assigned(PAGE.read_text()))
def test_every_assigned_notebook_has_exercises_and_an_on_your_own_section(name):
    notebook = NOTEBOOKS / f"{name}.ipynb"
    cells = json.loads(notebook.read_text())["cells"]
    headings = [line for c in cells if c["cell_type"] == "markdown" for line in "".join(c["source"]).splitlines()
                if line.startswith("#")]
    assert any(re.match(r"#+\s+On your own", h) for h in headings), f"{name} has no 'On your own' section"
    assert graded(notebook)[0] >= 1, f"{name} has no graded exercise (nbgrader metadata)"


def table(text):
    """The page's exercise table: [(lecture, notebook, what of it, exercises, on paper)], in order."""
    rows = re.findall(r"^\|\s*(\d+)\s*\|\s*`(\w+)`([^|]*)\|\s*(\d+)\s*\|\s*(\d+)\s*\|\s*$", text, flags=re.M)
    return [(int(lec), name, what.strip(), int(n), int(w)) for lec, name, what, n, w in rows]


@dataclasses.dataclass
class Exercise:
    notebook: str       # 09_measures_and_dimension
    label: str          # its number as the notebook writes it ("1b"), "" when it has none
    title: str          # "Exercise 1 (apply, pen and paper). Moran's equation with two scales"
    written: bool       # answered on paper: a graded markdown cell
    points: int


def exercises(path, sections=None):
    """The exercises of a notebook (of its `##` sections starting with ``sections``): one a graded
    nbgrader cell, titled by the exercise statement before it."""
    book = nbformat.read(path, as_version=4)
    kept = slides.pick(slides.sections(book), slides.Part(path.stem, sections), path.name)
    found, title = [], ""
    for cell in (c for sec in kept for c in sec.cells):
        grader = cell.metadata.get("nbgrader", {})
        if cell.cell_type == "markdown" and not grader:
            title = next((t for p in slides.paragraphs(cell.source) for t in [slides.exercise_title(p)] if t), title)
        if grader.get("grade"):
            label = re.match(r"Exercise\s+(\w*\d\w*)?", title)
            found.append(Exercise(path.stem, (label.group(1) or "") if label else "", title,
                                  cell.cell_type == "markdown", grader.get("points") or 0))
    return found


def lecture_exercises():
    """{lecture number: [(part, its exercises)]}, the parts as docs/slides/lectures.yaml lists them."""
    out = {}
    for number, lecture in enumerate(slides.load_lectures(), 1):
        out[number] = [(part, exercises(part.path(NOTEBOOKS), part.sections)) for part in lecture.parts]
    return out


LECTURE_EXERCISES = lecture_exercises()


def test_the_exercise_table_has_every_lecture_notebook_with_its_nbgrader_counts():
    rows = table(PAGE.read_text())
    expected = [(number, part.path(NOTEBOOKS).stem, len(found), sum(e.written for e in found))
                for number, parts in LECTURE_EXERCISES.items() for part, found in parts]
    assert [(lec, name, n, w) for lec, name, _, n, w in rows] == expected
    for (lec, name, what, n, w), (number, parts) in zip(rows, ((n, p) for n, ps in LECTURE_EXERCISES.items()
                                                                 for p, _ in ps)):
        if parts.sections:      # a notebook shown in part says which parts
            assert what and all(re.search(rf"\b{re.escape(s.rstrip('.'))}\b", what) for s in parts.sections
                                if s[0].isdigit()), f"{name}: the row says {what!r}, the lecture has {parts.sections}"


def homework():
    """{lecture number: its "At home" paragraph}."""
    text = PAGE.read_text()
    found = {}
    for match in re.finditer(r"^## Lecture (\d+)\b(.*?)(?=^## |\Z)", text, flags=re.M | re.S):
        paragraph = re.search(r"\*\*At home\.\*\*(.*?)(?:\n\n|\Z)", match.group(2), flags=re.S)
        found[int(match.group(1))] = " ".join(paragraph.group(1).split()) if paragraph else ""
    return found


HOMEWORK = homework()
NUMBERS = {"none": 0, "no": 0, "one": 1, "two": 2, "three": 3, "four": 4}


@pytest.mark.parametrize("number", sorted(LECTURE_EXERCISES))
def test_each_lectures_homework_counts_its_exercises_and_names_its_written_ones(number):
    paragraph = HOMEWORK[number]
    found = [e for _, part in LECTURE_EXERCISES[number] for e in part]
    written = [e for e in found if e.written]
    if not found:
        return
    total = re.search(r"\((\d+) exercises", paragraph)
    assert total and int(total.group(1)) == len(found), f"lecture {number}: {len(found)} exercises: {paragraph}"
    paper = re.search(r"\b(\w+)(?: of them)? on paper\b", paragraph)
    assert paper and NUMBERS.get(paper.group(1), -1) == len(written), \
        f"lecture {number}: {len(written)} on paper ({[e.title for e in written]}): {paragraph}"
    # the ones it names as on paper, "09's exercise 1" or "the tutorial's exercise 1b", are the written ones
    clause = paragraph[paper.end():]
    named = {(("00" if who == "the tutorial" else who), label)
             for who, label in re.findall(r"(\d\d|the tutorial)'s exercise (\w+)", clause)}
    assert named == {(e.notebook[:2], e.label) for e in written}, \
        f"lecture {number}: names {sorted(named)} as on paper, the written ones are {[e.title for e in written]}"


def test_the_grading_totals_are_the_notebooks():
    every = [e for path in sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb")) for e in exercises(path)]
    code, written = [e for e in every if not e.written], [e for e in every if e.written]
    text = " ".join(PAGE.read_text().split())
    claim = (f"{len(code)} auto-graded exercises worth {sum(e.points for e in code)} points, "
             f"{len(written)} written ones worth {sum(e.points for e in written)}")
    assert claim in text
    assert f"the written exercises ({len(written)}," in text


#: what a student has: the wheel, requirements-student.txt and the student edition (docs/guide/start-here.md)
CHECKOUT_ONLY = re.compile(r"^(make\b|\.\.?/?\.venv/|\S*papermill\b|\S*notebooks/)|\bnotebooks/\S+\.py\b")


@pytest.mark.parametrize("number", sorted(HOMEWORK))
def test_homework_asks_only_for_what_a_student_has(number):
    paragraph = HOMEWORK[number]
    for command in commands(paragraph):
        assert not CHECKOUT_ONLY.search(command), f"lecture {number}: {command!r} needs the project's checkout"
    assert "from the folder `notebooks/`" not in paragraph
    names = re.findall(r"`(\d\d_[a-z_]+)`", paragraph)
    for name, value in re.findall(r"`(\w+) = ([^`]+)`", paragraph):
        assert any(name in _parameters(NOTEBOOKS / f"{n}.ipynb") for n in names), \
            f"lecture {number}: {name} is a parameter of none of {names}"


def test_graded_counts_code_tests_and_written_answers():
    nb = {"cells": [
        {"cell_type": "code", "metadata": {"nbgrader": {"solution": True, "grade": False}}, "source": []},
        {"cell_type": "code", "metadata": {"nbgrader": {"solution": False, "grade": True}}, "source": []},
        {"cell_type": "markdown", "metadata": {"nbgrader": {"solution": True, "grade": True}}, "source": []},
        {"cell_type": "markdown", "metadata": {}, "source": []}]}
    path = Path(__file__).parent / "_course_page_probe.ipynb"
    try:
        path.write_text(json.dumps(nb))
        assert graded(path) == (2, 1)
    finally:
        path.unlink()
