"""`ifslib.automatic.fractal.collage`: the collage refined by Adam is least for the true maps, scales kept in range."""
import numpy as np
import torch

from ifslib.automatic import fractal
from ifslib.automatic.fractal.collage import clamp_scales
from common_testing import fractal_target


def test_collage_is_least_for_the_true_maps_and_refine_keeps_scales_in_range():
    truth, target = fractal_target(size=64)
    true_maps = truth.maps().detach().double()[:, :2].numpy()
    shifted = true_maps.copy()
    shifted[0, :, 2] += 0.03
    _, error = fractal.refine(np.stack([true_maps, shifted]), target, 0, 0.0, 2000)
    assert error[0] < 0.6 and error[1] > 1.5 * error[0]  # pixels
    wild = true_maps.copy()
    wild[0, :, :2] *= 1.5  # scale > 1: clipped back into range
    work, _ = fractal.refine(wild[None], target, 5, 0.002, 500)
    s = torch.linalg.svdvals(work[0, :, :, :2])
    assert float(s.max()) <= fractal.DEFAULT.max_scale + 1e-5 and float(s.min()) >= fractal.DEFAULT.min_scale - 1e-6


def test_the_contractivity_steps():
    maps = torch.tensor([[[2.0, 0.0, 0.5], [0.0, 0.1, 0.0]], [[0.5, 0.2, 0.0], [0.1, 0.4, 0.0]]])
    clamp_scales(maps, 0.2, 0.9)
    s = torch.linalg.svdvals(maps[..., :2])
    assert float(s.max()) <= 0.9 + 1e-6 and float(s.min()) >= 0.2 - 1e-6 and maps[0, 0, 2] == 0.5
