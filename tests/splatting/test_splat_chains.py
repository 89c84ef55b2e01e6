"""The splat renderer's chains are the chaos game's: the same points from the same seed, each with the map that made it."""
import numpy as np
import torch

from ifslib.core.geometry import patterns
from ifslib.core.raster.chaos import CHAINS, chaos_game
from ifslib.splatting.chains import chain_points


def test_chain_points_are_chaos_games_points_chain_by_chain():
    ifs = patterns.fern()
    rows = 3
    maps = ifs.to(torch.float64).maps().detach()
    points, picks = chain_points(maps, ifs.measure_probabilities(maps), rows, seed=5)
    game = chaos_game(ifs, rows * CHAINS, seed=5).reshape(rows, CHAINS, 2)
    assert np.array_equal(points.numpy(), game)
    maps = maps.numpy()
    sent = np.einsum("kcij,kcj->kci", maps[picks[1:].numpy()][..., :2, :2], points[:-1].numpy())
    sent += maps[picks[1:].numpy()][..., :2, 2]
    assert np.allclose(sent, points[1:].numpy(), atol=1e-12)
    assert picks.dtype == torch.int64 and int(picks.max()) < 4
