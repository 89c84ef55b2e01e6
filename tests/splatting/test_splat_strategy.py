"""The ``splat`` strategy through `ifslib.fit`: it is in the core's table by name, fits a start's maps so that its
attractor comes nearer the target, never returns worse than its start by the run's loss, and refuses bad starts."""
import pytest
import torch

import ifslib
from ifslib.core.fitting import strategies
from ifslib.core.geometry import patterns
from ifslib.core.raster.distance import distance_field
from ifslib.core.scoring.losses import loss
from ifslib.errors import IFSError
from ifslib.splatting.fit import SplatFit

THREE = torch.tensor([[[0.5, 0.0, -0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.0], [0.0, 0.5, 0.2], [0, 0, 1]]], dtype=torch.float64)
SIZE, STEPS = 48, 150


@pytest.fixture(scope="module")
def target():
    return ifslib.load_target(patterns.affine(THREE, depth=4, dtype=torch.float64), SIZE)


@pytest.fixture(scope="module")
def start():
    moved = THREE.clone()
    moved[:, :2, :] += 0.04 * torch.randn(3, 2, 3, generator=torch.Generator().manual_seed(0), dtype=torch.float64)
    return patterns.affine(moved, depth=4, dtype=torch.float64)


def attractor_loss(ifs, target) -> float:
    with torch.no_grad():
        return float(loss(distance_field(ifs, SIZE, "attractor"), target, "multiscale_distance"))


def test_splat_is_registered_by_its_home_module():
    from ifslib.splatting.strategy import run_splat
    assert "splat" in ifslib.names.STRATEGIES
    assert strategies.strategy("splat").run is run_splat


@pytest.mark.slow
def test_a_fit_brings_the_attractor_nearer(target, start):
    result = ifslib.fit(start, target, steps=STEPS, progress=False, strategy="splat", depth="attractor")
    history = result.history
    assert history.strategy == "splat" and history.cost == STEPS and len(history.loss) == STEPS
    assert history.judged == "attractor" and result.best.meta["splat"]["kept"] == "fitted"
    assert len(result.best.rules) == 3 and abs(sum(result.best.probabilities) - 1) < 1e-9
    assert result.best_loss == pytest.approx(attractor_loss(result.best, target), rel=1e-5)
    assert result.best_loss < attractor_loss(start, target)
    before, after = ifslib.evaluate(start, target), ifslib.evaluate(result.best, target)
    assert after["attractor_iou"] > before["attractor_iou"] + 0.1
    assert after["attractor_chamfer"] < before["attractor_chamfer"]
    assert "history" in result.best.meta  # what a saved fit records


@pytest.mark.parametrize("how, depth, why", [("off", "attractor", "is not below the start's"),
                                              ("flat", None, "cannot be drawn at depth 4")])
def test_the_start_is_kept_when_the_fit_scores_worse(target, start, monkeypatch, how, depth, why):
    import ifslib.splatting.strategy as module
    far = THREE.clone()
    if how == "off":
        far[:, :2, 2] += 0.3  # every copy moved off the figure
    else:
        far[0, 1, 1] = 0.0  # a flat map: no drawing at a depth takes it

    def worse(image, maps=None, start=None, options=None):
        ifs = patterns.affine(far, dtype=torch.float64)
        ifs.probabilities = (1 / 3, 1 / 3, 1 / 3)
        return SplatFit(ifs, (1.0,) * options.steps, 0, 0.0)

    monkeypatch.setattr(module, "fit_splat", worse)
    result = ifslib.fit(start, target, steps=5, progress=False, strategy="splat", depth=depth)
    compared = result.best.meta["splat"]
    assert compared["kept"] == "start" and why in compared["why"] and "the start kept" in compared["why"]
    assert torch.equal(result.best.points, start.points)
    if depth == "attractor":
        assert result.best_loss == pytest.approx(attractor_loss(start, target), rel=1e-5)


def test_bad_starts_and_settings_are_refused(target, start):
    grown = THREE.clone()
    grown[1, :2, :2] *= 2.5  # scale 1.25: no attractor
    with pytest.raises(IFSError, match=r"maps that contract, and T2 \(scale 1.25\)"):
        ifslib.fit(patterns.affine(grown, dtype=torch.float64), target, steps=5, progress=False, strategy="splat")
    with pytest.raises(IFSError, match="give an lr of at most 0.3"):
        ifslib.fit(start, target, steps=5, progress=False, strategy="splat", lr=1.0)
