"""Deep zooms into the attractor: 10x to 1000x windows against the float64 chaos game confined to the window,
the windowed field against brute force over the whole cut, costs that follow the window's pixels, bad windows."""
import numpy as np
import pytest
import torch
from scipy.spatial import cKDTree

import ifslib
import ifslib.geometry.reach
from ifslib.geometry import patterns
from ifslib.geometry.attractor import attractor_leaves, leaf_points
from ifslib.geometry.expand import expand_attractor
from ifslib.geometry.rules import rule_maps
from ifslib.raster.chaos import chaos_field, chaos_game, chaos_window, window_copies
from ifslib.raster.distance import Budget, attractor_leaves_for, distance_field, pixel_size
from ifslib.raster.nearest import pixel_centres
from ifslib.raster.render import figure_mask

SIZE = 48
TOLERANCE = 0.5  # pixels, the default
FIGURES = {"fern": patterns.fern, "random3_0": lambda: patterns.random_ifs(3, 0)}
#: Where the windows are centred (a chaos-game point of each seed). random3_0's copies overlap (the
#: similarity dimension of its scales is 3.1): around seed 7's point its certified cut grows about as
#: fast as the zoom even at the same pixels (2.9 million leaves at 300x of 48²), around seed 11's it does not.
CENTRES = {"fern": 7, "random3_0": 11}


def _window(ifs, zoom: float, seed: int = 7):
    """A square window ``1 / zoom`` wide centred on a chaos-game point of the attractor."""
    centre = chaos_game(ifs, 20_000, seed)[-1]
    half = 0.5 / zoom
    return (centre[0] - half, centre[1] - half, centre[0] + half, centre[1] + half)


@pytest.mark.parametrize("name", sorted(FIGURES))
@pytest.mark.parametrize("zoom", [10, 100, 1000])
def test_a_zoomed_window_agrees_with_the_chaos_game_confined_to_it(name, zoom):
    """Every chaos point lies on the attractor, so the certified field is at most the chaos field plus the
    tolerance; where the chaos game has covered the window, the chaos field is within a pixel of it."""
    ifs = FIGURES[name]()
    window = _window(ifs, zoom, CENTRES[name])
    px = pixel_size(SIZE, window)
    field = distance_field(ifs, SIZE, window=window, dtype=torch.float64, device="cpu").detach().numpy() / px
    chaos = chaos_field(ifs, SIZE, 100_000, seed=1, window=window).numpy() / px
    assert (field - chaos).max() <= TOLERANCE + 1e-9
    assert np.quantile(chaos - field, 0.99) <= TOLERANCE + 2.0  # the chaos game's coverage, not a bound
    drawn = figure_mask(ifs, SIZE, "attractor", window=window, dtype=torch.float64, device="cpu")
    by_chaos = figure_mask(ifs, SIZE, "attractor", window=window, method="chaos", points=100_000, seed=1)
    assert 0.01 < drawn.mean() < 0.9  # the figure crosses the window
    assert (drawn & by_chaos).sum() / (drawn | by_chaos).sum() > 0.85
    # every chaos point in the window lies within the tolerance and a pixel of a drawn pixel's centre
    x, y = pixel_centres(SIZE, dtype=torch.float64, window=window)
    centres = torch.stack([x, y], 1)[torch.from_numpy(drawn.reshape(-1))]
    points = torch.from_numpy(chaos_window(ifs, 20_000, window, seed=2))
    assert len(points) > 1000
    assert torch.cdist(points, centres).min(1).values.max() / px <= TOLERANCE + 1.0


@pytest.mark.parametrize("name", sorted(FIGURES))
def test_the_windowed_field_is_the_distance_to_the_whole_cut(name):
    """The window's leaves are a subset of the full cut at the window's tolerance, and the leaves it drops win
    no pixel: its field equals brute force over every leaf of the full cut."""
    ifs = FIGURES[name]().to(torch.float64)
    size, window = 12, _window(ifs, 10, CENTRES[name])
    eps = TOLERANCE * pixel_size(size, window)
    whole = expand_attractor(ifs, eps)
    x, y = pixel_centres(size, dtype=torch.float64, window=window)
    brute = torch.cdist(torch.stack([x, y], 1), whole.points).min(1).values.view(size, size)
    field = distance_field(ifs, size, window=window, device="cpu").detach()
    torch.testing.assert_close(field, brute, rtol=0, atol=1e-12)
    assert len(attractor_leaves_for(ifs, size, window)) < len(whole) / 2


def test_a_windowed_cut_keeps_every_leaf_word():
    """The words kept as parent links spell each leaf's point: recomputing them gives the points."""
    ifs = patterns.fern().to(torch.float64)
    leaves = attractor_leaves_for(ifs, 16, _window(ifs, 100))
    assert leaves.words.shape == (len(leaves), leaves.depth)
    torch.testing.assert_close(leaf_points(leaves, torch.arange(len(leaves))), leaves.points, rtol=0, atol=1e-12)
    some = torch.tensor([0, len(leaves) // 2, len(leaves) - 1])
    assert torch.equal(leaves.tree.select(some), leaves.words[some])


def test_the_cost_follows_the_window_pixels_not_the_zoom():
    """From 10x to 1000x, the same pixels need about as many leaves (the whole fern at 1000x's tolerance
    would need some 10^10)."""
    ifs = patterns.fern()
    counts = [len(attractor_leaves_for(ifs, 32, _window(ifs, zoom))) for zoom in (10, 100, 1000)]
    assert max(counts) < 3 * min(counts)
    maps = rule_maps(ifs.points, ifs.rules, "exact")
    with pytest.raises(ifslib.IFSError, match="needs more than"):
        attractor_leaves(maps, pixel_size(32, _window(ifs, 1000)) / 2, max_leaves=10 * max(counts))


@pytest.mark.parametrize("seed", [7, 11])
def test_sampled_leaves_confined_to_a_window_stand_for_its_attractor(seed):
    """Walkers started at the copies near a 1000x window end there, on leaves of the certified cut (each within
    the tolerance of the attractor): the field from them is never more than twice the tolerance below the
    certified field (where the certified cut fits the budget), and it draws about the chaos game's figure."""
    ifs = patterns.random_ifs(3, 0).to(torch.float64)
    window = _window(ifs, 1000, seed)
    px = pixel_size(SIZE, window)
    sampled = distance_field(ifs, SIZE, window=window, method="sampled", budget=Budget(samples=20_000),
                             device="cpu").detach() / px
    leaves = attractor_leaves_for(ifs, SIZE, window, sampled=True, samples=20_000)
    assert (ifslib.geometry.reach.to_window(leaves.points, window) <= 0).double().mean() > 0.2
    assert (leaves.error <= leaves.tolerance).all()
    chaos = chaos_field(ifs, SIZE, 100_000, seed=1, window=window) / px
    assert (sampled <= 0.83).double().mean() > 0.5 * (chaos <= 0.83).double().mean()  # it covers the figure
    if seed == 11:
        certified = distance_field(ifs, SIZE, window=window, device="cpu").detach() / px
        assert (certified - sampled).max() <= 2 * TOLERANCE + 1e-9
    torch.testing.assert_close(leaf_points(leaves, torch.arange(len(leaves))), leaves.points, rtol=0, atol=1e-12)


def test_the_chaos_game_of_a_window_stays_on_the_attractor_inside_it():
    """Points of a 1000x window lie in it and on the attractor (each is a copy of chaos-game points), and a
    window far from the attractor has none."""
    ifs = patterns.random_ifs(3, 0).to(torch.float64)
    window = _window(ifs, 1000, 11)
    points = chaos_window(ifs, 5000, window, seed=4)
    assert len(points) == 5000
    assert ((points >= window[:2]) & (points <= window[2:])).all()
    leaves = expand_attractor(ifs, 1e-5, window)
    # nearest leaf of each point by scipy's exact KD-tree query (a dense cdist here is 5000 x 58,000 distances)
    assert cKDTree(leaves.points.numpy()).query(points)[0].max() <= 1e-5 + 1e-12
    assert len(window_copies(ifs, (3.0, 3.0, 3.1, 3.1))[0]) == 0
    assert len(chaos_window(ifs, 100, (3.0, 3.0, 3.1, 3.1))) == 0


@pytest.mark.parametrize("window, message", [((0.1, 0.0, 0.1, 0.2), "zero or negative size"),
                                             ((0.0, 0.0, float("nan"), 1.0), "finite"),
                                             ((0.1, 0.2), "four numbers")])
def test_bad_windows_are_refused(window, message):
    fern = patterns.fern()
    for call in (lambda: ifslib.render(fern, 8, window=window), lambda: distance_field(fern, 8, window=window),
                 lambda: chaos_window(fern, 10, window), lambda: ifslib.render(fern, 8, window=window, method="chaos")):
        with pytest.raises(ifslib.IFSError, match=message):
            call()
