"""The splat fit on small images: it lowers its loss, keeps its maps contractive, fits gray levels' probabilities,
keeps the snapshots asked for, and refuses bad inputs."""
import dataclasses

import numpy as np
import pytest
import torch

from ifslib.errors import IFSError
from ifslib.measures.measure import cylinder_measure
from ifslib.core.geometry import patterns
from ifslib.splatting import SplatFitOptions, SplatOptions, fit_splat, splat_measure
from ifslib.splatting.fit import image_loss, start_maps

THREE = torch.tensor([[[0.5, 0.0, -0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.2], [0.0, 0.5, -0.2], [0, 0, 1]],
                      [[0.5, 0.0, 0.0], [0.0, 0.5, 0.2], [0, 0, 1]]], dtype=torch.float64)
QUICK = SplatFitOptions(steps=40, points_per_pixel=4.0, map_lr=0.03, reseed_every=10, seed=0, starts=1)


def sierpinski(size: int, p=(1 / 3, 1 / 3, 1 / 3)) -> np.ndarray:
    ifs = patterns.affine(THREE, dtype=torch.float64)
    ifs.probabilities = p
    return cylinder_measure(ifs, size)[0]


def scored(maps: torch.Tensor, p: torch.Tensor, mask: np.ndarray) -> float:
    """The fit's loss of ``maps`` on ``mask`` at its full size, from many points (the same for every IFS scored)."""
    density = splat_measure(maps.float(), p.float(), mask.shape[0], SplatOptions(points=2048 * 32, seed=9))
    return float(image_loss(density, torch.as_tensor(mask, dtype=torch.float64), "support"))


def test_a_random_start_moves_towards_the_figure():
    mask = sierpinski(32) > 0
    fit = fit_splat(mask, maps=3, options=QUICK)
    assert len(fit.ifs.rules) == 3 and len(fit.losses) == 40
    start = start_maps(None, 3, mask, torch.Generator().manual_seed(QUICK.seed)).maps().detach()  # the fit's own start
    before = scored(start, torch.full((3,), 1 / 3), mask)
    after = scored(fit.ifs.maps().detach(), torch.tensor(fit.ifs.probabilities), mask)
    assert after < 0.7 * before
    maps = fit.ifs.maps().detach()
    assert float(torch.linalg.svdvals(maps[:, :2, :2]).max()) < 1
    assert abs(sum(fit.ifs.probabilities) - 1) < 1e-9


def test_gray_levels_give_the_probabilities():
    truth = (0.6, 0.25, 0.15)
    image = sierpinski(32, truth)
    start = patterns.affine(THREE, dtype=torch.float64)
    start.probabilities = (1 / 3, 1 / 3, 1 / 3)
    options = SplatFitOptions(steps=60, points_per_pixel=16.0, map_lr=1e-4, probability_lr=0.05, anneal_noise=0.0,
                              reseed_every=0)
    fit = fit_splat(image, start=start, options=options)
    assert np.abs(np.array(fit.ifs.probabilities) - truth).max() < 0.08


def test_screened_starts_keep_the_least_loss(monkeypatch):
    import ifslib.splatting.fit as fit_module
    screens, starts = [], []
    real_fit, real_start = fit_module.fit_splat, fit_module.start_maps

    def spy_fit(image, maps=None, start=None, options=QUICK):
        out = real_fit(image, maps, start, options)
        screens.append((float(np.mean(out.losses[-10:])), out.ifs))
        return out

    def spy_start(start, m, mask, generator):
        starts.append(start)
        return real_start(start, m, mask, generator)

    monkeypatch.setattr(fit_module, "fit_splat", spy_fit)
    monkeypatch.setattr(fit_module, "start_maps", spy_start)
    real_fit(sierpinski(32) > 0, 3, None, SplatFitOptions(steps=3, starts=3, screen_steps=12, points_per_pixel=2.0))
    assert len(screens) == 3 and len(starts) == 4 and starts[:3] == [None] * 3
    assert starts[3] is min(screens, key=lambda s: s[0])[1]  # the fit goes on from the screen of least loss


def test_snapshots_keep_the_start_and_the_steps_asked_for_and_change_nothing():
    mask = sierpinski(32) > 0
    options = SplatFitOptions(steps=12, points_per_pixel=2.0, reseed_every=5, seed=0, starts=1)
    plain = fit_splat(mask, maps=3, options=options)
    fit = fit_splat(mask, maps=3, options=dataclasses.replace(options, snapshots=[12, 0, 6, 6]))
    assert plain.snapshots == () and [step for step, _ in fit.snapshots] == [0, 6, 12]
    assert torch.equal(fit.ifs.maps(), plain.ifs.maps())  # keeping snapshots draws nothing from the seeds
    start = start_maps(None, 3, mask, torch.Generator().manual_seed(0)).maps().detach().double()
    first, middle, last = (ifs.maps().detach() for _, ifs in fit.snapshots)
    assert torch.allclose(first, start, atol=1e-6)
    assert torch.equal(last, fit.ifs.maps()) and fit.snapshots[-1][1].probabilities == fit.ifs.probabilities
    assert not torch.equal(middle, first) and not torch.equal(middle, last)


def test_levels_run_coarse_to_fine_unless_the_fit_polishes_at_full_size(monkeypatch):
    import ifslib.splatting.fit as fit_module
    sizes, real = [], fit_module.splat_measure

    def spy(maps, p, size, options):
        sizes.append(size)
        return real(maps, p, size, options)

    monkeypatch.setattr(fit_module, "splat_measure", spy)
    mask = sierpinski(64) > 0
    options = SplatFitOptions(steps=10, points_per_pixel=2.0, reseed_every=0, seed=0, starts=1)
    fit_splat(mask, start=THREE, options=options)
    assert sizes == [16] * 6 + [32] * 2 + [64] * 2  # config.LEVEL_STEPS of 10 steps
    sizes.clear()
    fit_splat(mask, start=THREE, options=dataclasses.replace(options, coarse_to_fine=False))
    assert sizes == [64] * 10


def test_a_start_is_topped_up_to_the_maps_asked_for():
    fit = fit_splat(sierpinski(32) > 0, maps=4, start=THREE[:2], options=SplatFitOptions(steps=2, seed=1))
    assert len(fit.ifs.rules) == 4 and fit.seconds > 0


@pytest.mark.parametrize("image, kwargs, message", [
    (np.zeros((32, 32), bool), {"maps": 3}, "empty"),
    (np.ones((32, 20)), {"maps": 3}, "square"),
    (np.full((32, 32), np.nan), {"maps": 3}, "finite"),
    (np.ones((32, 32)) > 0, {"maps": 3}, "fills"),
    (sierpinski(32) > 0, {}, "number of maps"),
    (sierpinski(32) > 0, {"maps": 3, "options": {"steps": 3}}, "SplatFitOptions"),
])
def test_bad_inputs_are_refused(image, kwargs, message):
    with pytest.raises(IFSError, match=message):
        fit_splat(image, **kwargs)


@pytest.mark.parametrize("field, value", [("steps", 0), ("kind", "gray"), ("map_lr", -1.0), ("anneal_share", 2.0),
                                          ("points_per_pixel", 0), ("reseed_every", -1), ("progress", "yes"),
                                          ("snapshots", (-1,)), ("snapshots", (1501,)), ("snapshots", 3),
                                          ("coarse_to_fine", 1)])
def test_bad_options_are_refused(field, value):
    with pytest.raises(IFSError, match=field):
        SplatFitOptions(**{field: value})


@pytest.mark.skipif(torch.cuda.is_available(), reason="where CUDA is there, 'cuda' is a device to fit on")
def test_cuda_is_refused_where_torch_has_none():
    with pytest.raises(IFSError, match="device"):
        SplatFitOptions(device="cuda")
