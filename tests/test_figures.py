"""Image regression: each notebook's figure, regenerated at the ci preset, against a stored reference.

The notebooks run through papermill (as `make figures PRESET=ci` does) into a temporary folder;
each PNG they save is compared with ``tests/reference/<name>.png`` by SSIM (scikit-image), so a
change that alters a figure fails loudly. To accept an intended change, regenerate the references
with ``python notebooks/run.py --preset ci`` and copy ``build/figures-ci/*.png`` here.
"""
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from skimage.metrics import structural_similarity

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "tests" / "reference"
FIGURES = {"01_koch_iterations": "koch_iterations", "02_fitting_gallery": "fitting_gallery",
           "03_gradient_fields": "gradient_fields", "04_local_minima": "local_minima",
           "05_more_examples": "more_examples", "06_convergence_study": "convergence_study"}
MIN_SSIM = 0.9  # tolerates last-bit differences between CPUs; a changed figure scores far lower


def gray(path):
    return np.asarray(Image.open(path).convert("L"), dtype=float) / 255


@pytest.fixture(scope="session")
def ci_figures(tmp_path_factory):
    papermill = pytest.importorskip("papermill")
    out = tmp_path_factory.mktemp("figures")
    for book in FIGURES:
        path = ROOT / "notebooks" / f"{book}.ipynb"
        papermill.execute_notebook(str(path), str(out / path.name), cwd=str(path.parent), kernel_name="python3",
                                   parameters={"save_to": str(out)}, progress_bar=False)
    return out


@pytest.mark.parametrize("book", FIGURES)
def test_figure_matches_reference(ci_figures, book):
    name = FIGURES[book]
    new, ref = gray(ci_figures / f"{name}.png"), gray(REFERENCE / f"{name}.png")
    assert new.shape == ref.shape, f"{name}: size changed from {ref.shape} to {new.shape}"
    score = structural_similarity(new, ref, data_range=1.0)
    assert score >= MIN_SSIM, f"{name}: SSIM {score:.3f} < {MIN_SSIM} against tests/reference/{name}.png"


def test_ssim_catches_a_changed_figure():
    """The comparison is not vacuous: a reference against a visibly altered copy scores low."""
    ref = gray(REFERENCE / "koch_iterations.png")
    altered = ref.copy()
    altered[: ref.shape[0] // 2] = 1 - altered[: ref.shape[0] // 2]
    assert structural_similarity(altered, ref, data_range=1.0) < MIN_SSIM
