"""Every notebook run at its quick values, and each figure of that run against ``tests/reference/``.

Each notebook (``notebooks/[0-9][0-9]_*.ipynb`` and the glossary, as ``notebooks/run.py`` finds
them) is executed top to bottom by papermill into a temporary folder with the overrides of its
``metadata["ifslib"]["quick"]`` (``run.run_quick``, the code ``make figures PRESET=quick`` runs).
Any cell's error fails the test, and so does any failed ``assert``: the cells that check a lesson's
claims are plain asserts that hold at the quick and at the teaching values. The stored outputs
(the teaching run) are never compared with this run; tests/notebooks/test_stored_runs.py checks them.

Each figure of the quick run is compared with ``tests/reference/<name>.png`` by SSIM
(scikit-image), so a change that alters a figure fails loudly. To accept an intended change,
regenerate the references with ``python notebooks/run.py --preset quick`` and copy
``build/figures-quick/*.png`` here. Under ``make test``'s pytest-xdist workers a notebook's run
and its figure's comparison are one unit on one worker (``tests/conftest.py``), so the notebook
runs once.
"""
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from skimage.metrics import structural_similarity

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "tests" / "reference"
FIGURES = {"01_koch_iterations": "koch_iterations", "02_fitting_gallery": "fitting_gallery",
           "03_gradient_fields": "gradient_fields", "04_local_minima": "local_minima",
           "05_more_examples": "more_examples", "06_convergence_study": "convergence_study",
           "07_your_own_image": "your_own_image", "08_real_fractals": "real_fractals",
           "10_fractal_compression": "fractal_compression", "11_learned_guess": "learned_guess"}
MIN_SSIM = 0.9  # tolerates last-bit differences between CPUs; a changed figure scores far lower


def load_run():
    """``notebooks/run.py`` as a module (it is a script, not part of the package)."""
    spec = importlib.util.spec_from_file_location("ifslib_notebooks_run", ROOT / "notebooks" / "run.py")
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(ROOT / "notebooks"))  # run.py imports store.py beside it
    spec.loader.exec_module(module)
    return module


run = load_run()
BOOKS = {path.stem: path for path in run.notebooks()}

#: name -> (the figures' folder, or the error of the run), one run per notebook per worker.
_RUNS: dict = {}


def quick_run(book: str, tmp_path_factory) -> Path:
    """The folder holding the figure of ``book``'s quick run, running it on the first call."""
    if book not in _RUNS:
        folder = tmp_path_factory.mktemp(book)
        try:
            run.run_quick(BOOKS[book], folder, folder / "figures")
            _RUNS[book] = folder / "figures"
        except Exception as error:  # noqa: BLE001 - kept, so that the figure's test reports it without a rerun
            _RUNS[book] = error
    if isinstance(_RUNS[book], Exception):
        raise _RUNS[book]
    return _RUNS[book]


def test_every_notebook_is_run():
    """The lessons and the glossary are found by name, new ones included (09, 10, ...)."""
    assert {"00_tutorial", "01_koch_iterations", "glossary"} <= set(BOOKS)
    assert all(b.stem == "glossary" or b.stem[:2].isdigit() for b in BOOKS.values())
    assert set(FIGURES) <= set(BOOKS)


#: The lessons make test runs: the paper's first (00, 01, 03), about 55 s of CPU in all. The others' quick runs
#: (about 250 s of CPU, 08's splat fit and 07's the longest) are the ``slow`` tier: .ci/run runs them after make
#: test, and make test-stored runs every notebook again at its teaching values.
FIRST = ("00_", "01_", "03_")


def tiered(books):
    """``books`` as pytest parameters, those not in `FIRST` marked ``slow``."""
    return [pytest.param(b, marks=() if b.startswith(FIRST) else pytest.mark.slow) for b in books]


@pytest.mark.parametrize("book", tiered(sorted(BOOKS)))
def test_runs_at_quick_values(book, tmp_path_factory):
    executed = json.loads((quick_run(book, tmp_path_factory).parent / f"{book}.ipynb").read_text())
    # an exercise's locked test cell (nbgrader: grade, not solution) raises on a wrong answer, so a run
    # that passes has accepted the instructor's worked answer; here each test cell must have run
    for k, cell in enumerate(executed["cells"]):
        grader = cell["metadata"].get("nbgrader", {})
        if cell["cell_type"] == "code" and grader.get("grade") and not grader.get("solution"):
            assert cell.get("execution_count"), f"{book}, cell {k}: the test of {grader.get('grade_id')} did not run"
            assert not any(o["output_type"] == "error" for o in cell["outputs"]), f"{book}, cell {k}: its test failed"


@pytest.mark.parametrize("book", tiered(FIGURES))
def test_figure_matches_reference(book, tmp_path_factory):
    name = FIGURES[book]
    try:
        figures = quick_run(book, tmp_path_factory)
    except Exception as error:  # noqa: BLE001
        pytest.fail(f"{book} failed to run at its quick values (see test_runs_at_quick_values[{book}]): "
                    f"{type(error).__name__}", pytrace=False)
    assert (figures / f"{name}.png").exists(), f"{book} saved no {name}.png into its save_to folder"
    new, ref = gray(figures / f"{name}.png"), gray(REFERENCE / f"{name}.png")
    assert new.shape == ref.shape, f"{name}: size changed from {ref.shape} to {new.shape}"
    score = structural_similarity(new, ref, data_range=1.0)
    assert score >= MIN_SSIM, f"{name}: SSIM {score:.3f} < {MIN_SSIM} against tests/reference/{name}.png"


def gray(path):
    return np.asarray(Image.open(path).convert("L"), dtype=float) / 255


def test_ssim_catches_a_changed_figure():
    """The comparison is not vacuous: a reference against a visibly altered copy scores low."""
    ref = gray(REFERENCE / "koch_iterations.png")
    altered = ref.copy()
    altered[: ref.shape[0] // 2] = 1 - altered[: ref.shape[0] // 2]
    assert structural_similarity(altered, ref, data_range=1.0) < MIN_SSIM


def test_a_failed_assert_fails_the_run(tmp_path):
    """A notebook whose check fails does not pass: papermill raises with the assert's message."""
    nbformat = pytest.importorskip("nbformat")
    papermill = pytest.importorskip("papermill")
    book = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_code_cell("size = 128", metadata={"tags": ["parameters"]}),
        nbformat.v4.new_code_cell('assert size >= 100, "the lesson needs at least 100 px"')])
    book.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    book.metadata["ifslib"] = {"quick": {"size": 64}}
    path = tmp_path / "99_check.ipynb"
    nbformat.write(book, path)
    assert run.quick_parameters(path) == {"size": 64}
    with pytest.raises(papermill.PapermillExecutionError, match="the lesson needs at least 100 px"):
        run.run_quick(path, tmp_path / "out", tmp_path / "figures")
