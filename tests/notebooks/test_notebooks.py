"""The notebooks as stored: parameters cells, presets, kernelspec, and executed top to bottom.

nbval re-executes them (see pyproject.toml); these tests check what nbval does not.
"""
import ast
import json
import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
PAPER = yaml.safe_load((ROOT / "notebooks" / "params" / "paper.yaml").read_text())


def load(path):
    return json.loads(path.read_text())


def parameters_cell(book):
    tagged = [c for c in book["cells"] if "parameters" in c.get("metadata", {}).get("tags", [])]
    assert len(tagged) == 1, f"expected one cell tagged 'parameters', found {len(tagged)}"
    return tagged[0]


def parameters(book):
    """name -> default of the parameters cell, which must hold only literal assignments."""
    tree = ast.parse("".join(parameters_cell(book)["source"]))
    values = {}
    for node in tree.body:
        assert isinstance(node, ast.Assign) and len(node.targets) == 1, "parameters cell: only `name = literal`"
        values[node.targets[0].id] = ast.literal_eval(node.value)  # raises on anything derived
    return values


def test_the_notebooks_exist():
    assert [p.stem for p in NOTEBOOKS][:2] == ["00_explore", "00_tutorial"]
    assert [p.stem[:2] for p in NOTEBOOKS][2:7] == ["01", "02", "03", "04", "05"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_parameters_cell_holds_literals_and_save_to(path):
    values = parameters(load(path))
    assert len(values) >= 2
    if path.stem[:2] != "00":  # the figure notebooks save their PNG only when asked
        assert values.get("save_to") == "", "the ci preset must not write figures"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_stored_with_python3_kernel_and_executed_in_order(path):
    book = load(path)
    assert book["metadata"]["kernelspec"]["name"] == "python3"
    code = [c for c in book["cells"] if c["cell_type"] == "code"]
    assert [c["execution_count"] for c in code] == list(range(1, len(code) + 1)), "run top to bottom in a fresh kernel"
    errors = [o for c in code for o in c["outputs"] if o["output_type"] == "error"]
    assert not errors
    assert any("image/png" in o.get("data", {}) for c in code for o in c["outputs"]), "the figure is shown"


def test_paper_preset_names_only_real_parameters():
    by_name = {p.stem: parameters(load(p)) for p in NOTEBOOKS}
    assert set(PAPER) <= set(by_name), f"unknown notebooks in paper.yaml: {set(PAPER) - set(by_name)}"
    for name, section in PAPER.items():
        for key, value in section.items():
            assert key in by_name[name], f"{name}: {key!r} is not a parameter"
            assert type(value) is type(by_name[name][key]), f"{name}: {key} should be {type(by_name[name][key]).__name__}"


def test_checked_cells_exist():
    """Every notebook marks at least one cell of numbers for nbval to compare."""
    for path in NOTEBOOKS:
        code = [c for c in load(path)["cells"] if c["cell_type"] == "code"]
        assert any("nbval-check-output" in c["metadata"].get("tags", []) for c in code), path.name
        # the marker is a tag nbval reads, not a comment the reader sees in the book
        assert not any("NBVAL_" in "".join(c["source"]) for c in code), path.name


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_papermill_reads_every_parameter(path):
    """papermill parses the cell itself (its parser is stricter than Python's): it must see them all."""
    inspection = pytest.importorskip("papermill.inspection")
    assert set(inspection.inspect_notebook(str(path))) == set(parameters(load(path)))


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
    """What the reader will learn, what they need first, and how long it runs at both presets, measured."""
    first = "".join(load(path)["cells"][0]["source"])
    for heading in ("**What you will learn:**", "**What you need first:**", "**How long it runs**"):
        assert heading in first, f"{path.name}: its first cell has no {heading}"
    times = first[first.index("**How long it runs**"):]
    assert "ci preset" in times and "`make figures`" in times and times.count(" s") >= 2, times


#: The book's column holds this many characters of code (docs/_static/ifslib.css; browser_tests/test_book.py
#: checks in Chromium that no code cell scrolls sideways).
CODE_WIDTH = 88


@pytest.mark.parametrize("path", sorted((ROOT / "notebooks").glob("*.ipynb")), ids=lambda p: p.stem)
def test_code_fits_the_books_column(path):
    book = json.loads(path.read_text())
    wide = [line for cell in book["cells"] if cell["cell_type"] == "code"
            for line in "".join(cell["source"]).splitlines() if len(line) > CODE_WIDTH]
    assert not wide, f"{path.name}: {len(wide)} code lines over {CODE_WIDTH} characters, e.g. {wide[0]!r}"
