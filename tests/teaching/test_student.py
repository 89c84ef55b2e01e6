"""The student edition (``notebooks/student.py``) and the book's folded solutions, without a kernel.

The transformation is checked on small notebooks built here, in nbgrader's form, and on the real
notebooks as they are: their student edition must hold none of their solution lines. ``make
student`` executes the real edition; these tests run in well under a second.
"""
import sys
from pathlib import Path

import nbformat
from common_testing import load_module
import pytest

ROOT = Path(__file__).resolve().parents[2]
v4 = nbformat.v4




student = load_module("ifslib_student_edition", ROOT / "notebooks" / "student.py")
book_build = load_module("ifslib_docs_build", ROOT / "docs" / "build.py")

GRADER = {"grade": True, "solution": True, "locked": False, "points": 1, "grade_id": "koch_map",
          "schema_version": 3}
MATRIX = """T3 = None   # your answer: a 3 x 3 list or array
### BEGIN SOLUTION
r3 = np.sqrt(3)
T3 = [[1 / 6, r3 / 6, 1 / 2], [-r3 / 6, 1 / 6, r3 / 6], [0, 0, 1]]
### END SOLUTION
ifslib.exercises.check_koch_map(T3, 3);"""
FUNCTION = """def my_loss(image, target):
    \"\"\"The mean squared difference.\"\"\"
    ### BEGIN SOLUTION
    difference = image - target
    return (difference ** 2).mean()
    ### END SOLUTION
ifslib.exercises.check_loss(my_loss);"""
LOOP = """total = 0
for k in range(3):
    if k:
        ### BEGIN SOLUTION
        total += k
        ### END SOLUTION
    ### BEGIN SOLUTION
    total *= 2
    ### END SOLUTION
print(total)"""


def exercise(source, grade_id="koch_map"):
    meta = {"tags": ["exercise"], "nbgrader": {**GRADER, "grade_id": grade_id}}
    cell = v4.new_code_cell(source, metadata=meta, execution_count=3)
    cell.outputs = [v4.new_output("stream", name="stdout", text="T3: correct.\n")]
    return cell


def notebook(*cells):
    book = v4.new_notebook(cells=[v4.new_markdown_cell("# A lesson"),
                                  v4.new_code_cell("import numpy as np", execution_count=1), *cells])
    book.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    return book


def test_marked_block_becomes_one_stub_and_the_rest_stays():
    assert student.student_source(MATRIX) == ("T3 = None   # your answer: a 3 x 3 list or array\n"
                                              "...  # YOUR CODE HERE\n"
                                              "ifslib.exercises.check_koch_map(T3, 3);")


def test_stub_keeps_the_blocks_indentation_and_compiles():
    function = student.student_source(FUNCTION)
    assert '    """The mean squared difference."""\n    ...  # YOUR CODE HERE\nifslib' in function
    loop = student.student_source(LOOP)
    assert "        ...  # YOUR CODE HERE\n    ...  # YOUR CODE HERE\nprint(total)" in loop
    for source in (MATRIX, FUNCTION, LOOP):
        compile(student.student_source(source), "<cell>", "exec")
    namespace = {}
    exec(function.split("ifslib")[0], namespace)
    assert namespace["my_loss"](1, 2) is None  # the check then answers "not yet", no traceback


def test_a_cell_without_markers_is_left_as_it_is():
    for source in ("x = 1\n", "x = 1", "# BEGIN SOLUTION is said in a comment here\nx = 1", ""):
        assert student.student_source(source) == source


def test_edition_clears_outputs_and_keeps_metadata():
    instructor = notebook(exercise(MATRIX), exercise(FUNCTION, "loss"), v4.new_code_cell("x = 1", execution_count=5))
    edition = student.student_notebook(instructor, "lesson.ipynb")
    nbformat.validate(edition)
    code = [c for c in edition.cells if c.cell_type == "code"]
    assert all(c.outputs == [] and c.execution_count is None for c in code)
    assert code[1].metadata == instructor.cells[2].metadata  # tags and nbgrader's schema 3, unchanged
    assert code[2].metadata["nbgrader"]["grade_id"] == "loss"
    assert [c.get("id") for c in edition.cells] == [c.get("id") for c in instructor.cells]
    for cell in code:
        compile(cell.source, "<cell>", "exec")
    assert "BEGIN SOLUTION" not in nbformat.writes(edition)
    assert instructor.cells[2].outputs and "r3 = np.sqrt(3)" in instructor.cells[2].source  # a copy was changed
    assert not student.surviving_solutions(instructor, edition)
    assert student.solution_lines(instructor) >= {"r3 = np.sqrt(3)", "return (difference ** 2).mean()"}


@pytest.mark.parametrize("source, message", [
    ("a = 1\n### BEGIN SOLUTION\na = 2", "line 2: BEGIN SOLUTION without END SOLUTION"),
    ("a = 1\n### END SOLUTION", "line 2: END SOLUTION without BEGIN SOLUTION"),
    ("### BEGIN SOLUTION\n### BEGIN SOLUTION\na\n### END SOLUTION\n### END SOLUTION",
     "line 2: BEGIN SOLUTION inside the block opened at line 1"),
])
def test_unbalanced_markers_are_refused_naming_notebook_and_cell(source, message):
    bad = exercise(source)
    bad.id = "broken"
    instructor = notebook(exercise(MATRIX), bad)
    with pytest.raises(student.MarkerError) as raised:
        student.student_notebook(instructor, "lesson.ipynb")
    assert str(raised.value) == f"lesson.ipynb, cell 3 (id broken): {message}"


def test_write_edition_copies_plain_notebooks_and_refuses_bad_markers_before_writing(tmp_path, capsys):
    source, out = tmp_path / "notebooks", tmp_path / "student"
    source.mkdir()
    plain = notebook(v4.new_code_cell("x = 1", execution_count=2))
    nbformat.write(plain, source / "01_plain.ipynb")
    assert student.write_edition(out, source) == []
    assert (out / "01_plain.ipynb").read_bytes() == (source / "01_plain.ipynb").read_bytes()
    nbformat.write(notebook(exercise(MATRIX)), source / "00_tutorial.ipynb")
    nbformat.write(notebook(exercise("### BEGIN SOLUTION\nx = 1")), source / "02_bad.ipynb")
    (out / "01_plain.ipynb").unlink()
    assert student.main([str(out), "--source", str(source)]) == 2
    assert "02_bad.ipynb, cell 2" in capsys.readouterr().err
    assert not list(out.iterdir())  # nothing written when one notebook is refused


@pytest.mark.grading
def test_write_edition_releases_exercise_notebooks_through_nbgrader(tmp_path):
    source, out = tmp_path / "notebooks", tmp_path / "student"
    source.mkdir()
    nbformat.write(notebook(exercise(MATRIX)), source / "00_tutorial.ipynb")
    plain = notebook(v4.new_code_cell("x = 1", execution_count=2))
    nbformat.write(plain, source / "01_plain.ipynb")
    assert student.write_edition(out, source) == [out / "00_tutorial.ipynb"]
    assert (out / "01_plain.ipynb").read_bytes() == (source / "01_plain.ipynb").read_bytes()
    released = (out / "00_tutorial.ipynb").read_text()
    assert "YOUR CODE HERE" in released and "BEGIN SOLUTION" not in released


def test_book_shows_each_exercise_as_the_student_edition_has_it(tmp_path):
    instructor = notebook(exercise(MATRIX), exercise(FUNCTION, "loss"))
    nbformat.write(instructor, tmp_path / "in.ipynb")
    assert book_build.student_exercises(tmp_path / "in.ipynb", tmp_path / "out.ipynb") == 2
    shown = nbformat.read(tmp_path / "out.ipynb", as_version=4)
    nbformat.validate(shown)
    text = nbformat.writes(shown)
    assert "BEGIN SOLUTION" not in text and "r3 / 6" not in text
    assert student.CODE_STUB in shown.cells[2].source
    assert not [c for c in shown.cells if c.cell_type == "code" and c.outputs]  # no answer, no verdict


REAL = sorted((ROOT / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", REAL, ids=lambda p: p.stem)
def test_real_notebooks_student_edition_holds_no_solution_line(path):
    instructor = nbformat.read(path, as_version=4)
    edition = student.student_notebook(instructor, path.name)
    assert not student.surviving_solutions(instructor, edition)
    assert not any(student.has_solution(c) for c in edition.cells)
    for before, after in zip(instructor.cells, edition.cells):
        if after.cell_type == "code" and student.has_solution(before):
            compile(after.source, f"{path.name}: {after.get('id')}", "exec")


def test_check_fails_on_a_notebook_that_checks_answers_but_marks_none(tmp_path, capsys):
    source = tmp_path / "notebooks"
    source.mkdir()
    worked = notebook(v4.new_code_cell("leaf_count = lambda m, p, k: p * m ** k\n"
                                       "ifslib.exercises.run_answer(leaf_count, 'leaf count', 8, 1, 4)"))
    nbformat.write(worked, source / "00_tutorial.ipynb")
    assert student.main([str(tmp_path / "student"), "--source", str(source), "--check"]) == 1  # no kernel started
    assert "00_tutorial.ipynb: FAILED: runs ifslib.exercises" in capsys.readouterr().out


def test_book_check_finds_a_solution_shown_outside_a_fold(tmp_path):
    nbformat.write(notebook(exercise(MATRIX)), tmp_path / "lesson.ipynb")
    page = book_build.ROOT / "build" / "lesson.html"  # only named in the messages
    folded = "<p>T3 = None</p><details><summary>Show</summary><pre>r3 = np.sqrt(3)</pre></details>"
    assert book_build.check_folded(tmp_path / "lesson.ipynb", page, folded) == []
    shown = ('<pre><span class="n">r3</span> <span class="o">=</span> <span class="n">np</span><span class="o">.'
             '</span><span class="n">sqrt</span><span class="p">(</span><span class="mi">3</span>)</pre>')
    assert "r3 = np.sqrt(3)" in book_build.check_folded(tmp_path / "lesson.ipynb", page, shown)[0]


def test_quick_values_are_injected_after_the_parameters_cell_as_papermill_does():
    grading = student._grading()
    book = notebook(v4.new_code_cell("size = 128\nsteps = 200", metadata={"tags": ["parameters"]}),
                    v4.new_code_cell("print(size, steps)"))
    book.metadata["ifslib"] = {"quick": {"size": 64, "steps": 20}}
    quick = grading.with_quick_values(book)
    where = [c.source for c in quick.cells].index("size = 128\nsteps = 200")
    injected = quick.cells[where + 1]
    assert injected.metadata["tags"] == ["injected-parameters"]
    namespace = {}
    exec(quick.cells[where].source + "\n" + injected.source, namespace)
    assert (namespace["size"], namespace["steps"]) == (64, 20)
    plain = notebook(v4.new_code_cell("size = 128", metadata={"tags": ["parameters"]}))
    assert len(grading.with_quick_values(plain).cells) == len(plain.cells)   # no quick values: unchanged


def test_book_stubs_a_written_answers_model_answer_and_its_check_finds_one_shown(tmp_path):
    written = v4.new_markdown_cell("### BEGIN SOLUTION\n**Model answer.** By induction on $K$.\n\n"
                                   "**Rubric (2 points).** 1 point: the base case.\n### END SOLUTION",
                                   metadata={"nbgrader": {**GRADER, "grade_id": "proof", "points": 2}})
    nbformat.write(notebook(v4.new_markdown_cell("**Exercise 4.** Prove it."), written), tmp_path / "in.ipynb")
    assert book_build.student_exercises(tmp_path / "in.ipynb", tmp_path / "out.ipynb") == 1
    cell = nbformat.read(tmp_path / "out.ipynb", as_version=4).cells[-1]
    assert "Model answer" not in cell.source and "Rubric" not in cell.source
    page = book_build.ROOT / "build" / "lesson.html"  # only named in the messages
    assert book_build.check_folded(tmp_path / "in.ipynb", page, "<p>Prove it.</p><p>YOUR ANSWER HERE</p>") == []
    shown = "<p>Prove it.</p>\n**Model answer.** By induction on $K$.\n"
    assert book_build.check_folded(tmp_path / "in.ipynb", page, shown)
