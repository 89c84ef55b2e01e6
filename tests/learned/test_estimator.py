"""The guess: the target moved into the training pairs' framing and the maps moved back, contractive maps, the
shipped weights loaded without pickle, and clear errors."""
import numpy as np
import pytest
import torch
from scipy import ndimage

import ifslib
from ifslib.errors import IFSError
from ifslib.learned import config, guess
from ifslib.learned.estimator import clamped, expected_maps, framing, guess_maps, load_network, reframed
from ifslib.learned.network import GuessNet
from ifslib.learned.pairs import chaos_points, pair, picture


def test_framing_puts_the_figure_where_training_pairs_are():
    image, maps = pair(config.VALIDATION_TAG, 5)
    big = np.kron(image, np.ones((4, 4), dtype=bool))[16:, 16:]       # moved off-centre, 240 pixels a side
    big = np.pad(big, ((0, 16), (0, 16)))
    k, b = framing(big)
    moved = reframed(big, k, b).numpy() > 0
    near = ndimage.binary_dilation(image)                               # within a pixel: the box of pixels is
    assert (moved & near).sum() >= 0.98 * moved.sum()                   # up to a pixel wider than the points'
    assert (image & ndimage.binary_dilation(moved)).sum() >= 0.98 * image.sum()


def test_maps_come_back_to_the_target_frame():
    """A network that guesses the framed maps exactly gives the target's own maps back."""
    image, maps = pair(config.VALIDATION_TAG, 8)
    shifted = maps.copy()
    shifted[:, :, 2] += 0.1 - maps[:, :, :2] @ np.array([0.1, 0.1])   # the attractor moved by (0.1, 0.1)
    mask = picture(chaos_points(shifted, np.random.default_rng(0)), 128)

    class Oracle(GuessNet):
        def forward(self, pictures):
            k, b = framing(mask)
            framed = maps.copy()
            framed[:, :, 2] = k * shifted[:, :, 2] + b - shifted[:, :, :2] @ b
            out = torch.zeros(1, self.slots, 2, 3, dtype=torch.float64)
            out[0, :len(maps)] = torch.from_numpy(framed)
            return out, torch.tensor([[9.0] * len(maps) + [-9.0] * (self.slots - len(maps))])

    back = guess_maps(mask, Oracle(width=8))
    assert np.allclose(back, clamped(shifted), atol=1e-9)


def test_clamped_maps_are_contractive_and_contractive_maps_unchanged():
    maps = np.array([[[1.5, 0.2, 0.1], [0.0, 0.3, 0.0]], [[0.4, 0.1, -0.2], [0.1, 0.5, 0.3]]])
    out = clamped(maps)
    assert np.linalg.svd(out[:, :, :2], compute_uv=False).max() <= 0.95 + 1e-12
    assert np.allclose(out[1], maps[1]) and np.allclose(out[:, :, 2], maps[:, :, 2])


def test_the_shipped_guess_reads_a_fractal():
    truth = ifslib.random_fractals.random_ifs(4, 1000, extent=0.75)
    mask = ifslib.render(truth, 128, method="chaos", points=200_000).numpy() >= 0.5
    ifs = guess(mask)
    assert 2 <= len(ifs.rules) <= config.MAX_MAPS
    assert torch.linalg.svdvals(ifs.maps()[:, :2, :2].double()).max() < 1
    assert len(guess(mask, maps=3).rules) == 3


def test_the_expected_number_of_maps_undoes_the_presence_weight():
    sure, absent = np.log(config.PRESENT_WEIGHT * 1e6), -50.0       # a chance of 1 - 1e-6, and none
    assert expected_maps(np.array([sure] * 4 + [absent] * 252)) == 4
    even = np.log(config.PRESENT_WEIGHT)                            # odds of 1 after the weight: a chance of 1/2
    assert expected_maps(np.array([even] * 12 + [absent] * 244)) == 6
    assert expected_maps(np.full(256, absent)) == 2 and expected_maps(np.full(256, sure)) == config.MAX_MAPS


def test_weights_load_without_pickle(monkeypatch):
    calls = []
    real = torch.load
    monkeypatch.setattr(torch, "load", lambda *a, **k: calls.append(k) or real(*a, **k))
    load_network.cache_clear()
    try:
        load_network()
    finally:
        load_network.cache_clear()
    assert calls and calls[0].get("weights_only") is True


@pytest.mark.parametrize("bad", [np.zeros((8, 8), bool), np.ones((4, 5), bool), np.ones(3, bool)])
def test_bad_masks_are_refused(bad):
    with pytest.raises(IFSError, match="square mask"):
        guess(bad)


@pytest.mark.parametrize("maps", [1, 11, 2.5, True])
def test_a_bad_number_of_maps_is_refused(maps):
    mask = np.zeros((32, 32), bool)
    mask[8:24, 8:24] = True
    with pytest.raises(IFSError, match="maps"):
        guess(mask, maps=maps)
