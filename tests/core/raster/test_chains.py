"""The chaos game's one chain generator: its steps against a step-by-step walk, its picks, its inputs."""
import numpy as np
import pytest

import ifslib
from ifslib.core.raster.chains import fixed_points, pick_maps, walk


def _maps(ifs):
    return ifs.to(__import__("torch").float64).maps().detach().numpy()


def test_walk_is_a_step_by_step_chaos_game_with_numpys_choice():
    maps = _maps(ifslib.patterns.fern())
    p = np.array([0.01, 0.85, 0.07, 0.07])
    starts = fixed_points(maps)[[0, 1, 2, 3, 1]]
    steps = list(walk(maps, p, starts, 5, 20, np.random.default_rng(7)))
    # the reference: one Generator.choice a step, one matrix product per point
    rng, x = np.random.default_rng(7), starts.copy()
    for k in range(25):
        pick = rng.choice(4, size=len(x), p=p)
        x = np.einsum("nij,nj->ni", maps[pick, :2, :2], x) + maps[pick, :2, 2]
        if k >= 5:
            got = steps[k - 5]
            np.testing.assert_array_equal(got.pick, pick)
            np.testing.assert_allclose(np.stack([got.x, got.y], 1), x, rtol=0, atol=1e-15)
    assert len(steps) == 20


def test_each_pick_sends_the_previous_point_to_the_next():
    maps = _maps(ifslib.patterns.koch())
    m = len(maps)
    steps = list(walk(maps, np.full(m, 1 / m), np.zeros((64, 2)), 0, 10, np.random.default_rng(0)))
    for before, after in zip(steps, steps[1:]):
        chosen = maps[after.pick]
        x = chosen[:, 0, 0] * before.x + chosen[:, 0, 1] * before.y + chosen[:, 0, 2]
        np.testing.assert_array_equal(x, after.x)


def test_pick_maps_agrees_with_a_binary_search_above_and_below_its_switch():
    rng = np.random.default_rng(1)
    for m in (3, 40):
        cuts = np.cumsum(np.full(m, 1 / m))[:-1]
        u = rng.random(10_000)
        np.testing.assert_array_equal(pick_maps(u, cuts), np.searchsorted(cuts, u, side="right"))


def test_fixed_points_are_fixed():
    maps = _maps(ifslib.patterns.fern())
    points = fixed_points(maps)
    np.testing.assert_allclose(np.einsum("mij,mj->mi", maps[:, :2, :2], points) + maps[:, :2, 2], points, atol=1e-12)


@pytest.mark.parametrize("starts", [np.zeros(2), np.zeros((0, 2)), np.zeros((3, 3))])
def test_bad_starts_are_refused(starts):
    maps = _maps(ifslib.patterns.koch())
    with pytest.raises(ifslib.IFSError, match="starts"):
        next(walk(maps, np.full(len(maps), 1 / len(maps)), starts, 0, 1, np.random.default_rng(0)))
