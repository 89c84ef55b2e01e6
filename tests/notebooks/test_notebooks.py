"""The notebooks as written: their teaching and quick values, their checks, their lesson header, their code's width.

tests/notebooks/test_notebook_runs.py runs them at their quick values; these tests read them without running.
"""
import ast
import json
import re
from pathlib import Path

import pytest

from ifslib.errors import IFSError
from test_notebook_runs import run  # notebooks/run.py, loaded once

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
ALL = run.notebooks()  # the lessons and the glossary


def load(path):
    return json.loads(path.read_text())


def test_the_notebooks_exist():
    assert [p.stem for p in NOTEBOOKS][:2] == ["00_explore", "00_tutorial"]
    assert [p.stem[:2] for p in NOTEBOOKS][2:7] == ["01", "02", "03", "04", "05"]


@pytest.mark.parametrize("path", ALL, ids=lambda p: p.stem)
def test_parameters_cell_holds_literals_and_save_to(path):
    values = run.teaching_parameters(path)  # raises on anything but `name = literal`
    assert len(values) >= 1
    if path.stem[:2] not in ("00", "gl"):  # the figure notebooks save their PNG only when asked
        assert values.get("save_to") == "", "save_to must be empty: run.py sends the figure where it belongs"


@pytest.mark.parametrize("path", ALL, ids=lambda p: p.stem)
def test_quick_values_are_real_parameters(path):
    """Each quick override names a parameter of the cell, with a value of its type (`run.quick_parameters` checks)."""
    quick = run.quick_parameters(path)
    teaching = run.teaching_parameters(path)
    assert "save_to" not in quick, "save_to is set by run.py, not by the quick values"
    assert all(quick[k] != teaching[k] for k in quick), f"{path.name}: a quick value equal to its teaching value"


def test_quick_parameters_refuse_unknown_names_and_wrong_types(tmp_path):
    def book(quick):
        path = tmp_path / "99_x.ipynb"
        cell = {"cell_type": "code", "metadata": {"tags": ["parameters"]}, "source": "size = 128\nlr = 0.003\n",
                "outputs": [], "execution_count": None}
        path.write_text(json.dumps({"cells": [cell], "metadata": {"ifslib": {"quick": quick}},
                                    "nbformat": 4, "nbformat_minor": 5}))
        return path

    assert run.quick_parameters(book({"size": 64, "lr": 1})) == {"size": 64, "lr": 1}  # an int stands for a float
    with pytest.raises(IFSError, match="'sise' is not a parameter"):
        run.quick_parameters(book({"sise": 64}))
    with pytest.raises(IFSError, match="should have the type of its teaching value 128"):
        run.quick_parameters(book({"size": "64"}))
    with pytest.raises(IFSError, match="must be a dict"):
        run.quick_parameters(book([64]))


@pytest.mark.parametrize("path", ALL, ids=lambda p: p.stem)
def test_claims_are_checked_by_asserts(path):
    """Each notebook checks its lesson's claims with plain asserts (run at both presets), not with nbval's stored-output tags."""
    code = [c for c in load(path)["cells"] if c["cell_type"] == "code"]
    assert not any("nbval-check-output" in c["metadata"].get("tags", []) for c in code), \
        f"{path.name}: a cell is still tagged nbval-check-output; check its claim with an assert instead"
    asserts = [c for c in code if any(isinstance(n, ast.Assert) for n in ast.walk(ast.parse(source(c))))]
    exercises = [c for c in code if c["metadata"].get("nbgrader", {}).get("grade")]  # nbgrader's test cells assert
    assert asserts or exercises, f"{path.name}: no cell checks a claim of the lesson with an assert"


def source(cell) -> str:
    """A code cell's source as Python (IPython's magics and shell lines left out)."""
    magic = re.compile(r"\s*(%|!(?!=))")  # a continued line may start with "!=", which is Python
    return "\n".join(line for line in "".join(cell["source"]).splitlines() if not magic.match(line))


@pytest.mark.parametrize("path", ALL, ids=lambda p: p.stem)
def test_papermill_reads_every_parameter(path):
    """papermill parses the cell itself (its parser is stricter than Python's): it must see them all."""
    inspection = pytest.importorskip("papermill.inspection")
    assert set(inspection.inspect_notebook(str(path))) == set(run.teaching_parameters(path))


#: A tqdm bar as tqdm writes it (``40%|####  | 2/5 [...]``, or ``7it [00:01, 6.2it/s]`` without a total).
PROGRESS_BAR = re.compile(r"\d+%\|[^\r\n]*\||\[\d+:\d\d(?::\d\d)?(?:<[^,\]]*)?, *[^\]]*(?:/s|s/\w+)[^\]]*\]")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_progress_bar_is_stored(path):
    """A stored tqdm widget shows "0%" (its state is not stored) and a stderr bar is its redraws: store.py drops both."""
    for k, cell in enumerate(load(path)["cells"]):
        for out in cell.get("outputs", []):
            if out["output_type"] == "stream":
                text = "".join(out["text"])
            else:  # a tqdm widget's view has the bar as its text
                text = "".join(out.get("data", {}).get("text/plain", ""))
            assert not PROGRESS_BAR.search(text), f"{path.name}, cell {k}: a progress bar is stored: {text[:80]!r}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_each_notebook_opens_as_a_lesson(path):
    """What the reader will learn, what they need first, and how long it runs, with a time."""
    first = "".join(load(path)["cells"][0]["source"])
    for heading in (("What you will learn", "What you'll learn"), ("What you need",), ("How long it runs",)):
        assert any(h in first for h in heading), f"{path.name}: its first cell has no {heading[0]!r}"
    times = first[first.index("How long it runs"):]
    assert re.search(r"\d+ (s|min)\b", times), f"{path.name}: 'How long it runs' gives no time: {times[:120]!r}"


#: The book's column holds this many characters of code (docs/_static/ifslib.css; browser_tests/test_book.py
#: checks in Chromium that no code cell scrolls sideways).
CODE_WIDTH = 88


@pytest.mark.parametrize("path", sorted((ROOT / "notebooks").glob("*.ipynb")), ids=lambda p: p.stem)
def test_code_fits_the_books_column(path):
    book = json.loads(path.read_text())
    wide = [line for cell in book["cells"] if cell["cell_type"] == "code"
            for line in "".join(cell["source"]).splitlines() if len(line) > CODE_WIDTH]
    assert not wide, f"{path.name}: {len(wide)} code lines over {CODE_WIDTH} characters, e.g. {wide[0]!r}"
