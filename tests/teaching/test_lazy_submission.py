"""The lazy submission (course/lazy_submission.py, issue 53): its table names the notebooks' code answers, and
the copy it writes of a release changes those answer cells only. Without nbgrader: the release here is the
notebooks with each solution region cleared to nbgrader's stub, as ``generate_assignment`` clears it
(``course/grading.py --check`` autogrades the real one)."""
import ast
import copy
import importlib.util
import re
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("ifslib_course_lazy_submission", ROOT / "course" / "lazy_submission.py")
lazy = importlib.util.module_from_spec(spec)
spec.loader.exec_module(lazy)

SOLUTION = re.compile(r"^([ \t]*)### BEGIN SOLUTION.*?### END SOLUTION[ \t]*(\n|\Z)", re.M | re.S)


def graded_notebooks() -> list[Path]:
    return [path for path in sorted((ROOT / "notebooks").glob("*.ipynb"))
            if any(c.metadata.get("nbgrader") for c in nbformat.read(path, as_version=4).cells)]


def released(path: Path):
    """The notebook as released: code answers' solution regions cleared to the stub, outputs dropped."""
    book = nbformat.read(path, as_version=4)
    for cell in book.cells:
        if lazy.is_code_answer(cell):
            cell.source = SOLUTION.sub(lambda m: f"{m.group(1)}{lazy.STUB}{m.group(2)}", cell.source)
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    return book


@pytest.fixture(scope="module")
def release(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("release") / "ifs"
    folder.mkdir()
    for path in graded_notebooks():
        nbformat.write(released(path), folder / path.name)
    return folder


def code_answers() -> set[str]:
    return {lazy.grade_id(c) for path in graded_notebooks() for c in nbformat.read(path, as_version=4).cells
            if lazy.is_code_answer(c)}


def test_the_stub_is_the_one_nbgrader_writes():
    config = (ROOT / "course" / "nbgrader_config.py").read_text()
    stub = re.search(r"^c\.ClearSolutions\.code_stub = (\{.*\})", config, re.M).group(1)
    assert ast.literal_eval(stub)["python"] == lazy.STUB


def test_the_table_names_only_code_answers_of_the_notebooks():
    answers = code_answers()
    assert set(lazy.LAZY) <= answers, sorted(set(lazy.LAZY) - answers)
    assert set(lazy.UNANSWERED) <= answers and not set(lazy.UNANSWERED) & set(lazy.LAZY)


def test_every_code_answer_has_a_lazy_answer_or_is_listed_unanswered():
    missing = code_answers() - set(lazy.LAZY) - set(lazy.UNANSWERED)
    assert not missing, f"give these exercises a lazy answer in LAZY, or list them in UNANSWERED: {sorted(missing)}"


def test_the_copy_changes_only_the_answer_cells(release, tmp_path):
    out = tmp_path / "lazy" / "ifs"
    filled = lazy.write_lazy(release, out)
    assert sorted(filled) == sorted(lazy.LAZY)
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in release.iterdir())
    for path in sorted(release.glob("*.ipynb")):
        before, after = nbformat.read(path, as_version=4), nbformat.read(out / path.name, as_version=4)
        assert after.metadata == before.metadata and len(after.cells) == len(before.cells), path.name
        for old, new in zip(before.cells, after.cells):
            assert (new.cell_type, new.metadata) == (old.cell_type, old.metadata), path.name
            if lazy.is_code_answer(old) and lazy.grade_id(old) in lazy.LAZY:
                assert lazy.STUB not in new.source and new.source != old.source, lazy.grade_id(old)
                ast.parse(new.source)   # the answer cell still runs as Python
            else:
                assert new.source == old.source, lazy.grade_id(old) or path.name


def test_an_answer_goes_in_place_of_the_stub_at_its_indentation():
    source = f'def f(x):\n    """Doc."""\n    {lazy.STUB}\n\n\ny = f(1)'
    got = lazy.answered(source, lazy.Lazy("a = x\n\nreturn a", "import math\n"))
    assert got == 'import math\ndef f(x):\n    """Doc."""\n    a = x\n\n    return a\n\n\ny = f(1)'
    assert lazy.answered(f"x = None\n{lazy.STUB}", lazy.Lazy("x = 1")) == "x = None\nx = 1"
    with pytest.raises(ValueError, match="stub"):
        lazy.answered("x = 1", lazy.Lazy("x = 2"))


def test_the_instructors_own_notebook_is_left_alone():
    # no stub in a solved answer cell: filling it would raise, so a solved source is never taken for a release
    book = copy.deepcopy(nbformat.read(graded_notebooks()[0], as_version=4))
    with pytest.raises(ValueError, match="stub"):
        lazy.lazy_notebook(book)
