"""What nbgrader runs of a lesson (course/grading_run.py, ifslib/teaching/grading.py): the cells the checks
need at the grading sizes, the demonstrations skipped only while nbgrader executes."""
import importlib.util
import sys
from pathlib import Path

import nbformat
import pytest

from ifslib.teaching.grading import SKIPPED, cell_key, skip_cells

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("ifslib_course_grading_run", ROOT / "course" / "grading_run.py")
grading_run = importlib.util.module_from_spec(spec)
spec.loader.exec_module(grading_run)


def lesson(*sources, answer=None, test=None):
    """A notebook: a parameters cell, the given code cells, then an answer cell and a test cell."""
    cells = [nbformat.v4.new_code_cell("size = 256\nsteps = 1500", metadata={"tags": ["parameters"]})]
    cells += [nbformat.v4.new_code_cell(s) for s in sources]
    if answer is not None:
        cells.append(nbformat.v4.new_code_cell(answer, metadata={"nbgrader": {
            "grade": False, "solution": True, "locked": False, "grade_id": "answer", "schema_version": 3}}))
    if test is not None:
        cells.append(nbformat.v4.new_code_cell(test, metadata={"nbgrader": {
            "grade": True, "solution": False, "locked": True, "points": 1, "grade_id": "test",
            "schema_version": 3}}))
    book = nbformat.v4.new_notebook(cells=cells)
    book.metadata["ifslib"] = {"quick": {"size": 64}, "grading": {"steps": 10}}
    return book


def test_a_demonstration_no_check_reads_is_skipped():
    book = lesson("import numpy as np\nimport ifslib",           # 1: imports the answer reads
                  "fit = ifslib.fit(start, target, steps=steps)",  # 2: a long fit nobody reads
                  "target = ifslib.load_target('koch', size)",    # 3: the answer's target
                  "fig, ax = plt.subplots()\nax.plot(fit.losses)",  # 4: a picture of 2
                  answer="mine = np.ones(3) * target.size", test="assert mine is not None")
    assert grading_run.needed_cells(book) == {0, 1, 3, 5, 6}


def test_a_name_bound_before_it_is_read_in_a_cell_does_not_pull_in_earlier_cells():
    book = lesson("m = 3", "m = 4\nprint(m)", answer="m = 5\nx = m", test="assert x")
    assert grading_run.needed_cells(book) == {0, 3, 4}


def test_changes_in_place_and_method_calls_keep_the_cell():
    book = lesson("runs = []", "runs.append(1)", "fern.probabilities = [0.5, 0.5]", "fern = make()",
                  answer="total = len(runs) + len(fern.probabilities)", test="assert total")
    assert grading_run.needed_cells(book) == {0, 1, 2, 3, 4, 5, 6}


def test_names_read_inside_functions_and_comprehensions_count():
    book = lesson("scale = 2", "unused = 1", "def f(x):\n    return x * scale",
                  answer="values = [f(v) for v in range(3)]", test="assert values")
    assert grading_run.needed_cells(book) == {0, 1, 3, 4, 5}


def test_a_cell_that_cannot_be_read_is_kept():
    book = lesson("%matplotlib inline", "from helpers import *", "x = 1", answer="y = 2", test="assert y")
    assert {1, 2} <= grading_run.needed_cells(book)
    assert 3 not in grading_run.needed_cells(book)


def test_the_grading_cell_is_locked_after_the_parameters_and_sets_every_parameter():
    book = grading_run.with_grading_cell(lesson("x = 1", answer="y = 2", test="assert y"), "demo",
                                         {"size": 256, "steps": 1500})
    cell = book.cells[1]
    assert cell.metadata["nbgrader"]["locked"] and not cell.metadata["nbgrader"]["grade"]
    assert cell.metadata["nbgrader"]["grade_id"] == "demo-grading-run"
    namespace = {}
    exec(cell.source.replace('os.environ.get("NBGRADER_EXECUTION")', "False"), namespace)
    assert "size" not in namespace  # run by the student: nothing changes
    assert "size = 64\n" in cell.source and "steps = 10\n" in cell.source  # grading over quick over teaching
    assert repr(cell_key("x = 1")) in cell.source


def test_cell_key_ignores_surrounding_blanks_only():
    assert cell_key("a = 1\n\n  b = 2  \n") == cell_key("a = 1\nb = 2")
    assert cell_key("a = 1") != cell_key("a = 2")


@pytest.fixture
def shell():
    interactive = pytest.importorskip("IPython.core.interactiveshell")
    shell = interactive.InteractiveShell.instance()
    yield shell
    shell.input_transformers_cleanup[:] = [t for t in shell.input_transformers_cleanup
                                           if not getattr(t, "_ifslib_grading", False)]


def test_skip_cells_runs_pass_instead_of_the_named_cells_only(shell):
    shell.run_cell("ran = []")
    assert skip_cells([cell_key("ran.append('demo')")]) == 1
    shell.run_cell("ran.append('demo')")
    shell.run_cell("ran.append('answer')")
    shell.run_cell("  ran.append('demo')\n\n")   # the same cell, blanks aside
    assert shell.user_ns["ran"] == ["answer"]
    skip_cells([])  # a second call replaces the first's keys
    shell.run_cell("ran.append('demo')")
    assert shell.user_ns["ran"] == ["answer", "demo"]
    assert SKIPPED.startswith("pass")


def test_every_graded_lesson_keeps_its_checks_and_skips_something():
    """On the lessons themselves: every nbgrader cell kept, and each long lesson loses a demonstration."""
    skipped = {}
    for path in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        book = nbformat.read(path, as_version=4)
        if not any(c.metadata.get("nbgrader") for c in book.cells):
            continue
        needed = grading_run.needed_cells(book)
        assert all(i in needed for i, c in enumerate(book.cells)
                   if c.cell_type == "code" and c.metadata.get("nbgrader")), path.name
        skipped[path.stem] = sum(c.cell_type == "code" and i not in needed for i, c in enumerate(book.cells))
    assert sum(skipped.values()) >= 20, skipped
    sys.stdout.write(f"demonstrations skipped while grading: {skipped}\n")
