"""The students' lecture decks (``docs/slides.py`` -> ``build/slides/student/DECK.html``) hold none of
the instructor's answers, in their slides or their speaker notes: no line of a solution block (a
worked answer, a model answer and its rubric), no line of a hidden test, no output of an answer
cell. Checked on the real lecture file and notebooks, and on a small notebook built here; the
instructor's decks are checked to hold the worked answers, so that the check can see one.

The solution and hidden-test markers are read by ``notebooks/student.py``, the student edition's tool.
"""
import html
import re
from pathlib import Path

import nbformat
from common_testing import load_module
import pytest

pytestmark = pytest.mark.slow  # make test-slow: each deck is built for the students


ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = ROOT / "notebooks"
v4 = nbformat.v4

slides = load_module("ifslib_docs_slides", ROOT / "docs" / "slides.py")
student = load_module("ifslib_student_edition", ROOT / "notebooks" / "student.py")
LECTURES = slides.load_lectures()
ANSWER = {"grade": False, "solution": True, "locked": False, "points": None, "grade_id": "t-answer",
          "schema_version": 3}
TEST = {"grade": True, "solution": False, "locked": True, "points": 1, "grade_id": "t-answer-test",
        "schema_version": 3}
WRITTEN = {"grade": True, "solution": True, "locked": False, "points": 2, "grade_id": "t-written",
           "schema_version": 3}


def _text(fragment: str) -> str:
    """What a page shows of an HTML fragment: its words and code, a block's on lines of their own."""
    blocks = re.sub(r"</?(p|pre|div|li|ul|ol|br|tr|td|th|h\d|table|details|summary|aside|section)\b[^>]*>", "\n",
                    fragment)
    return html.unescape(re.sub(r"<[^>]+>", "", blocks))


def _flat(text: str) -> str:
    """``text`` as it reads once rendered: markdown's emphasis and code marks dropped, spaces collapsed."""
    return " ".join(re.sub(r"[*`]", "", text).split())


def deck_text(columns) -> str:
    """Every slide's body and speaker notes of a deck, as text."""
    return "\n".join(_text(s.body) + "\n" + _text("".join(s.notes)) for column in columns for s in column)


def leaks(text: str, secret: set[str]) -> list[str]:
    """The lines of ``secret`` that ``text`` shows: as a whole line, or (long ones, which markdown
    may have rendered) inside a line."""
    lines = {line.strip() for line in text.splitlines()}
    flat = _flat(text)
    return sorted(s for s in secret if s in lines or (len(_flat(s)) >= 30 and _flat(s) in flat))


def _notebooks():
    return {path.stem: nbformat.read(path, as_version=4) for path in sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb"))}


NOTEBOOK_CELLS = _notebooks()


def _shown_lines() -> set[str]:
    """Every line a student sees anyway: the lines outside solution blocks and hidden tests of any notebook."""
    found = set()
    for book in NOTEBOOK_CELLS.values():
        for cell in book.cells:
            for piece in student.split(cell.source):
                if not piece.solution:
                    found.update(line.strip() for line in student.HIDDEN.sub("", piece.text).splitlines())
    return found


SHOWN = _shown_lines()
#: the lines of the solution blocks (code and written) of every notebook that a student never sees
SOLUTIONS = set().union(*(student.solution_lines(book) for book in NOTEBOOK_CELLS.values())) - SHOWN
HIDDEN = set().union(*(student.hidden_lines(book) for book in NOTEBOOK_CELLS.values())) - SHOWN


def _answer_outputs() -> set[str]:
    """The printed lines of the answer cells' stored outputs that no other cell of their notebook prints."""
    found = set()
    for book in NOTEBOOK_CELLS.values():
        other = {line.strip() for cell in book.cells if cell.cell_type == "code" and not student.is_exercise(cell)
                 for out in cell.get("outputs", []) for line in out.get("text", "").splitlines()}
        found |= {line.strip() for cell in book.cells if cell.cell_type == "code" and student.is_exercise(cell)
                  for out in cell.get("outputs", []) for line in out.get("text", "").splitlines()
                  if len(line.strip()) >= 4} - other
    return found


ANSWER_OUTPUTS = _answer_outputs()


@pytest.fixture(scope="module")
def decks():
    """{(deck, student): its columns}, for every lecture of the lecture file."""
    return {(lec.deck, edition): slides.lecture_columns(lec, NOTEBOOKS, edition)
            for lec in LECTURES for edition in (False, True)}


def test_the_notebooks_have_answers_to_hide():
    assert len(SOLUTIONS) > 100 and HIDDEN and ANSWER_OUTPUTS


@pytest.mark.parametrize("deck", [lec.deck for lec in LECTURES])
def test_a_students_deck_shows_no_solution_hidden_test_or_answer_output(decks, deck):
    columns = decks[(deck, True)]
    text = deck_text(columns)
    assert not leaks(text, SOLUTIONS), f"{deck}: solution lines in the student's deck"
    assert not leaks(text, HIDDEN), f"{deck}: hidden-test lines in the student's deck"
    lines = {line.strip() for line in text.splitlines()}
    assert not ANSWER_OUTPUTS & lines, f"{deck}: an answer cell's output in the student's deck"
    raw = "".join(s.body + "".join(s.notes) for column in columns for s in column)
    for marker in ("BEGIN SOLUTION", "END SOLUTION", "HIDDEN TESTS", "Model answer", "Worked answer"):
        assert marker not in raw, f"{deck}: {marker!r} in the student's deck"


def test_the_check_sees_the_worked_answers_in_the_instructors_decks(decks):
    """The instructor's decks carry the worked answers in their notes: the check finds them there."""
    found = set()
    for lec in LECTURES:
        found.update(leaks(deck_text(decks[(lec.deck, False)]), SOLUTIONS))
    assert len(found) >= 0.95 * len(SOLUTIONS)


@pytest.mark.parametrize("deck", [lec.deck for lec in LECTURES])
def test_both_decks_have_the_same_slides(decks, deck):
    """The student's deck differs from the instructor's only in the notes."""
    instructor, student_deck = decks[(deck, False)], decks[(deck, True)]
    assert [[(s.kind, s.title, s.body) for s in c] for c in instructor] == \
        [[(s.kind, s.title, s.body) for s in c] for c in student_deck]


def _lesson(tmp_path):
    """A notebook with a code exercise (an answer that prints and draws, a hidden test) and a
    written one, written into ``tmp_path`` as 09_lesson.ipynb."""
    answer = v4.new_code_cell("leaves = None\n### BEGIN SOLUTION\nleaves = 8 ** 4   # the secret line\n"
                              "### END SOLUTION\nprint(leaves)", metadata={"nbgrader": ANSWER})
    answer.outputs = [v4.new_output("stream", name="stdout", text="4096 SECRET-OUTPUT\n"),
                      v4.new_output("display_data", data={"image/png": "iVBORw0KGgoSECRET", "text/plain": "<Figure>"})]
    test = v4.new_code_cell("assert leaves\n### BEGIN HIDDEN TESTS\nassert leaves == 4096  # hidden\n"
                            "### END HIDDEN TESTS", metadata={"nbgrader": TEST})
    written = v4.new_markdown_cell("YOUR ANSWER\n\n### BEGIN SOLUTION\n**Model answer.** The bound is $s^K d_0$.\n"
                                   "Rubric: one point for the induction.\n### END SOLUTION",
                                   metadata={"nbgrader": WRITTEN})
    book = v4.new_notebook(cells=[
        v4.new_markdown_cell("# 9. A lesson\n\nWhat it teaches."),
        v4.new_markdown_cell("## On your own\n\n### Exercise 1 (code). Count the leaves\n\nHow many leaves at depth 4?"
                             "\n\n<details><summary>Hint</summary>Count depth 1 first.</details>"),
        answer, test,
        v4.new_markdown_cell("**Exercise 2 (prove, pen and paper).** Prove the bound."), written])
    nbformat.write(book, tmp_path / "09_lesson.ipynb")
    return slides.Lecture("t", "Lecture 9: t", (slides.Part("09", None),))


def test_a_students_deck_keeps_the_statement_and_hint_and_drops_the_rest(tmp_path):
    lecture = _lesson(tmp_path)
    for edition in (False, True):
        columns = slides.lecture_columns(lecture, tmp_path, edition)
        exercises = [s for column in columns for s in column if s.kind == "exercise"]
        assert [s.title for s in exercises] == ["Exercise 1 (code). Count the leaves",
                                                "Exercise 2 (prove, pen and paper)"]
        notes = "".join(n for s in exercises for n in s.notes)
        page = slides.deck_html(lecture, columns, tmp_path, edition)
        assert "How many leaves" in exercises[0].body and "Count depth 1 first" in notes
        assert "SECRET-OUTPUT" not in page and "iVBORw0KGgoSECRET" not in page     # no answer cell's output
        assert "assert leaves == 4096" not in page                                 # no test, hidden or not
        if edition:
            assert "the secret line" not in page and "Model answer" not in page and "Rubric" not in page
            assert "...  # YOUR CODE HERE" in notes          # the answer cell as the student edition has it
        else:
            assert "the secret line" in notes and "Rubric: one point" in notes


def test_build_writes_a_students_deck_beside_each_instructors(tmp_path):
    lecture = _lesson(tmp_path)
    out = tmp_path / "slides"
    assert slides.build([lecture], tmp_path, out) == []
    instructor, student_deck = (out / "t.html").read_text(), (out / "student" / "t.html").read_text()
    assert "the secret line" in instructor and "the secret line" not in student_deck
    # reveal.js from build/npm, by a path relative to each deck's own folder
    assert f'src="{slides.npm_path(out, "reveal.js")}/dist/reveal.js"' in instructor
    assert f'src="{slides.npm_path(out / "student", "reveal.js")}/dist/reveal.js"' in student_deck
    assert 'href="student/t.html"' in (out / "index.html").read_text()
