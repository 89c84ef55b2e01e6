"""random_fractals: the sigma-factor sampler's random IFSs, seeded, contractive, framed."""
import numpy as np
import pytest
import torch

import ifslib


def test_random_ifs_is_seeded_contractive_and_in_the_frame():
    a, b = ifslib.random_fractals.random_ifs(3, seed=7), ifslib.random_fractals.random_ifs(3, seed=7)
    assert torch.equal(a.points, b.points) and len(a.rules) == 3 and a.name == "random3_7"
    assert not torch.equal(a.points, ifslib.random_fractals.random_ifs(3, seed=8).points)
    for maps in (2, 5):
        ifs = ifslib.random_fractals.random_ifs(maps, seed=1).to(torch.float64)
        lo, hi = ifslib.core.geometry.rules.singular_values(ifs.maps().detach())
        assert (hi < ifslib.random_fractals.MAX_RANDOM_SCALE).all() and (lo > 0).all()
        sigma = float((hi + 2 * lo).sum())  # the sigma-factor of Anderson and Farrell
        assert (5 + maps) / 2 - 1e-9 <= sigma <= (6 + maps) / 2 + 1e-9
        # the box from certified leaves (within 0.005 of the attractor), as random_ifs places it: a fair
        # chaos-game sample visits a thin map's tip too rarely to measure the box by
        leaves = ifslib.core.geometry.attractor.attractor_leaves(ifs.maps().detach(), 0.005, max_leaves=4_000_000)
        box = leaves.points.numpy()
        extent = (box.max(0) - box.min(0)).max()
        assert 0.75 <= extent <= 0.82 and np.abs(box).max() <= 0.45  # random_ifs cut within 4% of the radius
        cloud = ifslib.chaos_game(ifs, 200_000, seed=2)  # and the attractor's points lie in that box
        assert (cloud >= box.min(0) - 0.01).all() and (cloud <= box.max(0) + 0.01).all()


@pytest.mark.parametrize("maps", [0, 1000, 2.5])
def test_random_ifs_refuses_bad_numbers_of_maps(maps):
    with pytest.raises(ifslib.IFSError, match="maps"):
        ifslib.random_fractals.random_ifs(maps)
