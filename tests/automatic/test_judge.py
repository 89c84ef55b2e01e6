"""`ifslib.automatic.fractal.judge`: the short chaos games that rank IFSs mark what the float64 chaos game marks."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib.errors import IFSError


def test_chaos_occupancy_marks_the_pixels_of_the_float64_chaos_game_for_a_batch():
    from ifslib.core.geometry.rules import chaos_probabilities
    from ifslib.automatic.fractal.judge import chaos_occupancy
    from ifslib.core.raster.chaos import chaos_game

    systems = [ifslib.random_fractals.random_ifs(3, 1), ifslib.random_fractals.random_ifs(3, 5)]
    maps = torch.stack([s.maps().detach() for s in systems])
    batched = chaos_probabilities(maps)
    for one, s in zip(batched, systems):  # a batch is normalised one IFS at a time, as each alone
        torch.testing.assert_close(one, chaos_probabilities(s.maps()))
    drawn = chaos_occupancy(maps[:, :, :2, :], 64, chains=100, steps=200).numpy()
    for picture, s in zip(drawn, systems):
        points = chaos_game(s, 400_000)
        col, row = np.floor((points[:, 0] + 0.5) * 64).astype(int), np.floor((0.5 - points[:, 1]) * 64).astype(int)
        inside = (col >= 0) & (col < 64) & (row >= 0) & (row < 64)
        reference = np.zeros((64, 64), bool)
        reference[row[inside], col[inside]] = True
        assert (picture & ~reference).sum() <= 0.01 * picture.sum()  # float32 points stay on the attractor's pixels
        assert ifslib.iou(picture, reference) >= 0.85  # 20,000 points find most of them
    with pytest.raises(IFSError, match="shape"):
        chaos_occupancy(maps[0], 64)
