"""The notebooks' run by nbval: at another thread count than their stored outputs, and their figures.

nbval (see pyproject.toml) executes every notebook with ``IFSLIB_THREADS=1`` (set in
``tests/conftest.py`` unless the caller set it) and compares each cell
tagged ``nbval-check-output`` with its stored output (after ``notebooks/sanitize.cfg``). The stored
outputs were made at 2 threads by ``notebooks/store.py``, which records the count in the
notebook's metadata, so torch's CPU kernels sum in another order in the tests: a checked output
that carries a rounding error's last digits, or a fit result that flips with the summation order,
fails there rather than on a reader's machine. Here:

* each notebook's stored thread count must differ from the tests' (else nbval's comparison would
  not cross thread counts);
* each figure of nbval's run (the figure notebooks write it to ``IFSLIB_FIGURES``, which
  ``tests/conftest.py`` sets: an empty ``save_to`` falls back on it) is compared with
  ``tests/reference/<name>.png`` by SSIM (scikit-image), so a change that alters a figure fails
  loudly. pytest runs ``notebooks/`` before ``tests/`` (``testpaths``); when this file runs without
  nbval's run (``pytest tests/``), a missing figure is made by running its notebook with papermill.
  To accept an intended change, regenerate the references with ``python notebooks/run.py --preset
  ci`` and copy ``build/figures-ci/*.png`` here.

Each notebook is executed once by ``make test``; under its pytest-xdist workers a notebook's figure is
compared on the worker that ran it (``tests/conftest.py`` groups them).
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

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "tests" / "reference"
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
FIGURES = {"01_koch_iterations": "koch_iterations", "02_fitting_gallery": "fitting_gallery",
           "03_gradient_fields": "gradient_fields", "04_local_minima": "local_minima",
           "05_more_examples": "more_examples", "06_convergence_study": "convergence_study",
           "07_your_own_image": "your_own_image", "08_real_fractals": "real_fractals"}
MIN_SSIM = 0.9  # tolerates last-bit differences between CPUs; a changed figure scores far lower


def gray(path):
    return np.asarray(Image.open(path).convert("L"), dtype=float) / 255


def sanitizers():
    """(pattern, replacement) pairs of notebooks/sanitize.cfg, the ones nbval applies."""
    config = configparser.ConfigParser(interpolation=None)
    config.read(ROOT / "notebooks" / "sanitize.cfg")
    return [(re.compile(config[s]["regex"]), config[s]["replace"]) for s in config.sections()]


def masked(text: str, rules) -> str:
    """``text`` after the sanitizers, as nbval compares it."""
    for pattern, replacement in rules:
        text = pattern.sub(replacement, text)
    return text


def figure_of(book: str, out: Path) -> Path:
    """The figure nbval's run of notebook ``book`` saved, or (without that run: ``pytest tests/``) papermill's."""
    figure = Path(os.environ["IFSLIB_FIGURES"]) / f"{FIGURES[book]}.png"
    if not figure.exists():
        papermill = pytest.importorskip("papermill")
        path = ROOT / "notebooks" / f"{book}.ipynb"
        papermill.execute_notebook(str(path), str(out / path.name), cwd=str(path.parent), kernel_name="python3",
                                   parameters={"save_to": str(figure.parent)}, progress_bar=False)
    return figure


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_stored_outputs_were_made_at_another_thread_count(path):
    stored = json.loads(path.read_text())["metadata"].get("ifslib", {}).get("threads")
    assert stored is not None, f"{path.name}: no thread count recorded; store it with python notebooks/store.py"
    if str(stored) == os.environ["IFSLIB_THREADS"] and os.environ.get("IFSLIB_THREADS_SET_BY") != "conftest":
        pytest.skip(f"IFSLIB_THREADS={stored} was fixed by the caller, the count the outputs were stored at: this run "
                    "compares them at the same count (the default run, at 1 thread, compares across counts)")
    assert str(stored) != os.environ["IFSLIB_THREADS"], (
        f"{path.name} was stored at {stored} threads and nbval runs it at IFSLIB_THREADS={os.environ['IFSLIB_THREADS']}: its checked "
        "cells would not be compared across thread counts; run the tests at another count")


@pytest.mark.parametrize("book", FIGURES)
def test_figure_matches_reference(book, tmp_path):
    name = FIGURES[book]
    new, ref = gray(figure_of(book, tmp_path)), gray(REFERENCE / f"{name}.png")
    assert new.shape == ref.shape, f"{name}: size changed from {ref.shape} to {new.shape}"
    score = structural_similarity(new, ref, data_range=1.0)
    assert score >= MIN_SSIM, f"{name}: SSIM {score:.3f} < {MIN_SSIM} against tests/reference/{name}.png"


def test_ssim_catches_a_changed_figure():
    """The comparison is not vacuous: a reference against a visibly altered copy scores low."""
    ref = gray(REFERENCE / "koch_iterations.png")
    altered = ref.copy()
    altered[: ref.shape[0] // 2] = 1 - altered[: ref.shape[0] // 2]
    assert structural_similarity(altered, ref, data_range=1.0) < MIN_SSIM


def test_the_sanitizers_mask_timings_but_not_float_noise():
    """The checked cells' comparison is not vacuous: float noise in a checked cell's text is a difference."""
    rules = sanitizers()
    assert masked("error 4.44e-16, took 1.5 s\n", rules) == "error 4.44e-16, took TIME\n"
    assert masked("error 4.44e-16, took 1.5 s\n", rules) != masked("error 8.88e-16, took 2.5 s\n", rules)
