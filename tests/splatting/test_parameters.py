"""The contractive parameterization: any raw numbers give maps of scale below the bound; given maps come back."""
import numpy as np
import pytest
import torch

from ifslib.errors import IFSError
from ifslib.splatting import ContractiveMaps
from ifslib.splatting.parameters import random_raw


def test_every_raw_point_gives_contractive_maps():
    raw = torch.randn(200, 6, generator=torch.Generator().manual_seed(0), dtype=torch.float64) * 20
    maps = ContractiveMaps(raw, max_scale=0.9).maps().detach()  # a saturated logit reaches the bound itself
    assert maps.shape == (200, 3, 3) and torch.equal(maps[:, 2], torch.tensor([0.0, 0, 1]).expand(200, 3))
    assert float(torch.linalg.svdvals(maps[:, :2, :2])[:, 0].max()) <= 0.9 + 1e-12


@pytest.mark.parametrize("lin", [[[0.3, 0.1], [-0.2, 0.4]], [[0.0, 0.5], [0.5, 0.0]], [[-0.6, 0.0], [0.0, 0.2]]])
def test_maps_come_back_with_their_reflection(lin):
    maps = torch.eye(3, dtype=torch.float64)[None].clone()
    maps[0, :2, :2], maps[0, :2, 2] = torch.tensor(lin), torch.tensor([0.1, -0.2])
    back = ContractiveMaps.from_maps(maps, dtype=torch.float64).maps().detach()
    assert torch.allclose(back, maps, atol=1e-12)


def test_gradient_reaches_every_parameter_and_too_large_maps_are_clamped():
    params = ContractiveMaps(random_raw(4, (0.2, 0.4), torch.Generator().manual_seed(1)))
    weights = torch.randn(4, 3, 3, generator=torch.Generator().manual_seed(2))
    (params.maps() * weights).sum().backward()  # not a norm: a norm does not see the rotations
    assert (params.raw.grad.abs().sum(0) > 0).all()
    big = ContractiveMaps.from_maps(torch.eye(3)[None] * 1.5)
    assert float(torch.linalg.svdvals(big.maps().detach()[0, :2, :2]).max()) < big.max_scale


def test_bad_parameters_are_refused():
    with pytest.raises(IFSError, match="shape"):
        ContractiveMaps(torch.zeros(3, 5))
    with pytest.raises(IFSError, match="finite"):
        ContractiveMaps(torch.full((2, 6), float("nan")))
    with pytest.raises(IFSError, match="max_scale"):
        ContractiveMaps(torch.zeros(2, 6), max_scale=1.0)
    with pytest.raises(IFSError, match="scales"):
        random_raw(2, (0.5, 0.2), torch.Generator())
    with pytest.raises(IFSError, match="finite"):
        ContractiveMaps.from_maps(np.full((1, 3, 3), np.inf))
