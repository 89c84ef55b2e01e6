"""The lessons' exercises keep nbgrader's form, read from the notebooks without running them.

An auto-graded exercise is three cells: a statement with a hint to open before answering, the
student's cell (``solution``, not graded) holding the worked answer between ``### BEGIN SOLUTION``
and ``### END SOLUTION``, and a locked test cell (``grade``, ``grade_id`` the answer's plus
``-test``) with visible asserts and hidden ones. A written exercise is a statement with a hint and a
markdown answer cell (``solution`` and ``grade``) whose model answer and rubric lie between the
solution markers. The checks compute their own truth: a test cell may use the exercises' harness
(``ifslib.exercises``: running the student's function with the library's own switched off, reading
an answer as a matrix, the fit targets' pictures), which holds no answer key
(``tests/teaching/test_exercises.py`` checks that), and nothing else of it. The statement is the
last markdown cell before the answer (a code cell that sets the exercise up may sit between them).
Exercises sit in the sections they practise or under an "On your own" heading, which every lesson
with exercises has but the tutorial, whose four parts are exercises throughout.
"""
import json
import re
from pathlib import Path

import pytest

import ifslib.teaching.exercises as harness

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"


def cells(path):
    return json.loads(path.read_text())["cells"]


def text(cell):
    return "".join(cell["source"])


def grader(cell):
    return cell["metadata"].get("nbgrader", {})


def uses_the_form(path):
    """A notebook with at least one locked test cell uses this form."""
    return any(grader(c).get("locked") and grader(c).get("grade") for c in cells(path))


LESSONS = [p for p in sorted(NOTEBOOKS.glob("*.ipynb")) if uses_the_form(p)]


def test_the_lessons_of_issue_44_use_the_form():
    names = {p.stem for p in LESSONS}
    assert {"02_fitting_gallery", "03_gradient_fields", "04_local_minima", "06_convergence_study",
            "08_real_fractals"} <= names


def statement(book, k):
    """The last markdown cell before cell ``k``, over set-up code cells (none of them graded)."""
    j = k - 1
    while j > 0 and book[j]["cell_type"] == "code" and not grader(book[j]):
        j -= 1
    return book[j]


def exercises(path):
    """(kind, statement, answer, test) for each exercise; test is None for a written one."""
    book = cells(path)
    found = []
    for k, cell in enumerate(book):
        meta = grader(cell)
        if cell["cell_type"] == "code" and meta.get("solution") and not meta.get("grade"):
            found.append(("code", statement(book, k), cell, book[k + 1] if k + 1 < len(book) else None))
        elif cell["cell_type"] == "markdown" and meta.get("solution") and meta.get("grade"):
            found.append(("written", statement(book, k), cell, None))
    return found


@pytest.mark.parametrize("path", LESSONS, ids=lambda p: p.stem)
def test_each_exercise_has_a_hint_an_answer_and_a_check(path):
    found = exercises(path)
    assert found, f"{path.name}: no exercise"
    for kind, statement, answer, test in found:
        name = grader(answer)["grade_id"]
        assert grader(answer)["schema_version"] == 3 and not grader(answer).get("locked")
        assert name.startswith(path.stem + "-"), f"{name}: grade_id should start with the notebook's name"
        assert statement["cell_type"] == "markdown" and "<summary>Hint</summary>" in text(statement), \
            f"{name}: the cell before the answer should state the exercise with a hint to open"
        body = text(answer)
        assert body.count("### BEGIN SOLUTION") == 1 and body.count("### END SOLUTION") == 1, name
        if kind == "written":
            assert grader(answer).get("points", 0) > 0 and "Rubric" in body, f"{name}: points and a rubric"
            continue
        meta = grader(test)
        assert test["cell_type"] == "code" and meta.get("grade") and meta.get("locked"), \
            f"{name}: the cell after the answer should be its locked check"
        assert not meta.get("solution") and meta.get("points", 0) > 0 and meta["grade_id"] == name + "-test"
        check = text(test)
        assert "assert " in check.split("### BEGIN HIDDEN TESTS")[0], f"{name}: no visible assert"
        assert "### BEGIN HIDDEN TESTS" in check and "### END HIDDEN TESTS" in check, f"{name}: no hidden tests"
        used = set(re.findall(r"ifslib\.exercises\.(\w+)", check))
        assert used <= set(harness.__all__), f"{name}: the check must compute its own truth, not read {used}"


@pytest.mark.parametrize("path", LESSONS, ids=lambda p: p.stem)
def test_grade_ids_are_unique_and_the_exercises_sit_under_on_your_own(path):
    book = cells(path)
    ids = [grader(c)["grade_id"] for c in book if grader(c)]
    assert len(ids) == len(set(ids)), f"{path.name}: a grade_id is used twice"
    heading = [k for k, c in enumerate(book) if c["cell_type"] == "markdown"
               and any(line.startswith("#") and "On your own" in line for line in text(c).splitlines())]
    assert heading or path.stem == "00_tutorial", f"{path.name}: no 'On your own' section"


def test_the_form_is_told_apart_from_a_broken_one(tmp_path):
    statement = {"cell_type": "markdown", "metadata": {}, "source": ["**Exercise.** <details><summary>Hint</summary>x"]}
    answer = {"cell_type": "code", "metadata": {"nbgrader": {
        "solution": True, "grade": False, "locked": False, "grade_id": "99_x-a", "schema_version": 3}},
        "source": ["x = None\n### BEGIN SOLUTION\nx = 1\n### END SOLUTION"]}
    test = {"cell_type": "code", "metadata": {"nbgrader": {
        "solution": False, "grade": True, "locked": True, "points": 1, "grade_id": "99_x-a-test",
        "schema_version": 3}}, "source": ["assert x == 1\n### BEGIN HIDDEN TESTS\n### END HIDDEN TESTS"]}
    heading = {"cell_type": "markdown", "metadata": {}, "source": ["## On your own"]}
    path = tmp_path / "99_x.ipynb"
    path.write_text(json.dumps({"cells": [heading, statement, answer, test]}))
    test_each_exercise_has_a_hint_an_answer_and_a_check(path)
    test_grade_ids_are_unique_and_the_exercises_sit_under_on_your_own(path)
    test["source"] = ["assert x == 1"]   # no hidden tests
    path.write_text(json.dumps({"cells": [heading, statement, answer, test]}))
    with pytest.raises(AssertionError, match="no hidden tests"):
        test_each_exercise_has_a_hint_an_answer_and_a_check(path)
    statement["source"] = ["**Exercise.** no hint"]
    path.write_text(json.dumps({"cells": [heading, statement, answer, test]}))
    with pytest.raises(AssertionError, match="hint"):
        test_each_exercise_has_a_hint_an_answer_and_a_check(path)
