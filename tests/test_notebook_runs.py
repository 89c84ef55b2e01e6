"""Every notebook run once more, at another thread count: its checked cells and its figure.

nbval (see pyproject.toml) re-executes the notebooks with ``IFSLIB_THREADS=2`` (set in
``tests/conftest.py`` unless the caller set it) and compares each cell marked
``# NBVAL_CHECK_OUTPUT`` with its stored output. Here papermill runs every notebook a second time,
with a different thread count (1, or 2 where nbval ran at 1), so torch's CPU kernels sum in a
different order, and with ``save_to`` set so the figure notebooks write their PNGs:

* each checked cell must print the same text as stored (after ``notebooks/sanitize.cfg``, as nbval
  compares it): a checked output that carries a rounding error's last digits, or a fit result that
  flips with the summation order, fails here rather than on a reader's machine;
* each figure is compared with ``tests/reference/<name>.png`` by SSIM (scikit-image), so a change
  that alters a figure fails loudly. To accept an intended change, regenerate the references with
  ``python notebooks/run.py --preset ci`` and copy ``build/figures-ci/*.png`` here.
"""
import configparser
import json
import os
import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from skimage.metrics import structural_similarity

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "tests" / "reference"
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
FIGURES = {"01_koch_iterations": "koch_iterations", "02_fitting_gallery": "fitting_gallery",
           "03_gradient_fields": "gradient_fields", "04_local_minima": "local_minima",
           "05_more_examples": "more_examples", "06_convergence_study": "convergence_study",
           "07_your_own_image": "your_own_image", "08_real_fractals": "real_fractals"}
MIN_SSIM = 0.9  # tolerates last-bit differences between CPUs; a changed figure scores far lower
CHECK = "# NBVAL_CHECK_OUTPUT"


def gray(path):
    return np.asarray(Image.open(path).convert("L"), dtype=float) / 255


def other_thread_count() -> str:
    """The thread count of this second run: 1, unless nbval's run (IFSLIB_THREADS) already used 1."""
    return "2" if os.environ.get("IFSLIB_THREADS") == "1" else "1"


def sanitizers():
    """(pattern, replacement) pairs of notebooks/sanitize.cfg, the ones nbval applies."""
    config = configparser.ConfigParser(interpolation=None)
    config.read(ROOT / "notebooks" / "sanitize.cfg")
    return [(re.compile(config[s]["regex"]), config[s]["replace"]) for s in config.sections()]


def printed(cell, rules) -> str:
    """The text a code cell showed (streams, plain-text results, errors), sanitized."""
    parts = []
    for out in cell.get("outputs", []):
        if out["output_type"] == "stream":
            parts.append("".join(out["text"]))
        elif out["output_type"] in ("execute_result", "display_data") and "text/plain" in out["data"]:
            parts.append("".join(out["data"]["text/plain"]))
        elif out["output_type"] == "error":
            parts.append(f"{out['ename']}: {out['evalue']}")
    text = "".join(parts)
    for pattern, replacement in rules:
        text = pattern.sub(replacement, text)
    return text


def checked_cells(book):
    """source -> cell, for the code cells marked for nbval."""
    return {"".join(c["source"]): c for c in book["cells"]
            if c["cell_type"] == "code" and "".join(c["source"]).startswith(CHECK)}


@pytest.fixture(scope="session")
def runs(tmp_path_factory):
    """Every notebook executed by papermill at the other thread count; figures saved beside them."""
    papermill = pytest.importorskip("papermill")
    out = tmp_path_factory.mktemp("runs")
    saved = os.environ.get("IFSLIB_THREADS")
    os.environ["IFSLIB_THREADS"] = other_thread_count()  # the kernels inherit the environment
    try:
        for path in NOTEBOOKS:
            parameters = {"save_to": str(out)} if path.stem in FIGURES else {}
            papermill.execute_notebook(str(path), str(out / path.name), cwd=str(path.parent), kernel_name="python3",
                                       parameters=parameters, progress_bar=False)
    finally:
        if saved is None:
            del os.environ["IFSLIB_THREADS"]
        else:
            os.environ["IFSLIB_THREADS"] = saved
    return out


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_checked_cells_print_the_same_at_another_thread_count(runs, path):
    rules = sanitizers()
    stored = checked_cells(json.loads(path.read_text()))
    rerun = checked_cells(json.loads((runs / path.name).read_text()))
    assert stored and set(stored) == set(rerun)
    for source, cell in stored.items():
        expected, got = printed(cell, rules), printed(rerun[source], rules)
        assert got == expected, (f"{path.name}: a checked cell printed differently with IFSLIB_THREADS="
                                 f"{other_thread_count()}:\n--- stored\n{expected}\n--- now\n{got}\n--- cell\n{source}")


@pytest.mark.parametrize("book", FIGURES)
def test_figure_matches_reference(runs, book):
    name = FIGURES[book]
    new, ref = gray(runs / f"{name}.png"), gray(REFERENCE / f"{name}.png")
    assert new.shape == ref.shape, f"{name}: size changed from {ref.shape} to {new.shape}"
    score = structural_similarity(new, ref, data_range=1.0)
    assert score >= MIN_SSIM, f"{name}: SSIM {score:.3f} < {MIN_SSIM} against tests/reference/{name}.png"


def test_ssim_catches_a_changed_figure():
    """The comparison is not vacuous: a reference against a visibly altered copy scores low."""
    ref = gray(REFERENCE / "koch_iterations.png")
    altered = ref.copy()
    altered[: ref.shape[0] // 2] = 1 - altered[: ref.shape[0] // 2]
    assert structural_similarity(altered, ref, data_range=1.0) < MIN_SSIM


def test_a_changed_checked_output_is_caught():
    """The comparison is not vacuous either: float noise in a checked cell's text is a difference."""
    cell = {"outputs": [{"output_type": "stream", "name": "stdout", "text": ["error 4.44e-16, took 1.5 s\n"]}]}
    noisy = {"outputs": [{"output_type": "stream", "name": "stdout", "text": ["error 8.88e-16, took 2.5 s\n"]}]}
    rules = sanitizers()
    assert printed(cell, rules) == "error 4.44e-16, took TIME\n"
    assert printed(cell, rules) != printed(noisy, rules)
