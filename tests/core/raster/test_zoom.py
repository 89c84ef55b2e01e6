"""Deep zooms into the attractor: 10x to 1000x windows against the float64 chaos game confined to the window,
the windowed field against brute force over the whole cut, costs that follow the window's pixels, bad windows;
and the chaos game itself, a fair sample of the invariant measure at any number of points."""
import functools

import numpy as np
import pytest
import torch
from scipy import stats
from scipy.spatial import cKDTree

import ifslib
import ifslib.core.geometry.reach
from ifslib.core.geometry import patterns, random_fractals
from ifslib.core.geometry.attractor import attractor_leaves, leaf_points
from ifslib.core.geometry.expand import expand_attractor
from ifslib.core.geometry.rules import rule_maps
from ifslib.core.raster.chaos import CHAINS, burn_in_steps, chaos_field, chaos_game, chaos_window, window_copies
from ifslib.core.raster.distance import Budget, attractor_leaves_for, distance_field, pixel_size
from ifslib.measures.measure import CylinderOptions, cylinder_measure
from ifslib.core.raster.nearest import pixel_centres
from ifslib.core.raster.render import figure_mask

SIZE = 48
TOLERANCE = 0.5  # pixels, the default
FIGURES = {"fern": patterns.fern, "random3_0": lambda: random_fractals.random_ifs(3, 0)}
#: Points of each attractor the windows are centred on, by figure and number (chaos-game points, written out so
#: that the windows, and what is measured in them, do not move with the chaos game's sampling).
POINTS = {("fern", 7): (0.18454736886074358, -0.19226229635527686),
          ("random3_0", 7): (-0.09070924101878264, 0.18423015069028234),
          ("random3_0", 11): (-0.24582361504158826, -0.22133675763896327)}
#: The point of each figure its windows of every zoom are centred on. random3_0's copies overlap (the
#: similarity dimension of its scales is 3.1): around point 7 its certified cut grows about as
#: fast as the zoom even at the same pixels (2.9 million leaves at 300x of 48²), around point 11 it does not.
CENTRES = {"fern": 7, "random3_0": 11}


def _window(ifs, zoom: float, point: int = 7):
    """A square window ``1 / zoom`` wide centred on the attractor's point ``point`` of `POINTS`."""
    centre = POINTS[ifs.name, point]
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


@pytest.mark.parametrize("point", [7, 11])
def test_sampled_leaves_confined_to_a_window_stand_for_its_attractor(point):
    """Walkers started at the copies near a 1000x window end there, on leaves of the certified cut (each within
    the tolerance of the attractor): the field from them is never more than twice the tolerance below the
    certified field (where the certified cut fits the budget), and it draws about the chaos game's figure."""
    ifs = random_fractals.random_ifs(3, 0).to(torch.float64)
    window = _window(ifs, 1000, point)
    px = pixel_size(SIZE, window)
    sampled = distance_field(ifs, SIZE, window=window, method="sampled", budget=Budget(samples=20_000),
                             device="cpu").detach() / px
    leaves = attractor_leaves_for(ifs, SIZE, window, sampled=True, samples=20_000)
    assert (ifslib.core.geometry.reach.to_window(leaves.points, window) <= 0).double().mean() > 0.2
    assert (leaves.error <= leaves.tolerance).all()
    chaos = chaos_field(ifs, SIZE, 100_000, seed=1, window=window) / px
    assert (sampled <= 0.83).double().mean() > 0.5 * (chaos <= 0.83).double().mean()  # it covers the figure
    if point == 11:
        certified = distance_field(ifs, SIZE, window=window, device="cpu").detach() / px
        assert (certified - sampled).max() <= 2 * TOLERANCE + 1e-9
    torch.testing.assert_close(leaf_points(leaves, torch.arange(len(leaves))), leaves.points, rtol=0, atol=1e-12)


def test_the_chaos_game_of_a_window_stays_on_the_attractor_inside_it():
    """Points of a 1000x window lie in it and on the attractor (each is a copy of chaos-game points), and a
    window far from the attractor has none."""
    ifs = random_fractals.random_ifs(3, 0).to(torch.float64)
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


# The chaos game itself: at any n its points are draws of the invariant measure, checked against the exact masses of
# `cylinder_measure` on a coarse grid.

#: Cells a side of the grid the chaos game's histogram is read on: odd, so that no dyadic cylinder's edge (the
#: halvings') falls on a cell edge inside the frame, and the segment y = 0 is a cell's middle.
CELLS = 7
#: Chance that a fair chaos game fails one of the histogram tests below at its seed.
ALPHA = 1e-3
#: Cylinders placed whole while crossing a cell edge are narrower than this many cells: their share, which bounds
#: every cell's error, stays near 1e-6, a count of 1 in 10^6 points.
EXACT = CylinderOptions(smallest=1e-6)


def _halves():
    """Two halvings of the segment [-0.4, 0.4] x {0} onto its two halves: the invariant measure is uniform on it."""
    return patterns.affine([[[0.5, 0, -0.2], [0, 0.5, 0]], [[0.5, 0, 0.2], [0, 0.5, 0]]])


def _lopsided():
    """The Sierpinski triangle with probabilities 0.5, 0.3, 0.2: a measure far from its maps' default one."""
    triangle = patterns.sierpinski_triangle()
    triangle.probabilities = (0.5, 0.3, 0.2)
    return triangle


FAIR = {"koch": patterns.koch, "halves": _halves, "lopsided": _lopsided}


@functools.lru_cache(maxsize=None)
def _exact(name: str) -> tuple[np.ndarray, float]:
    """The measure's cell masses (flat, row-major) and the share of mass `cylinder_measure` placed, its error bound."""
    masses, placed = cylinder_measure(FAIR[name]().to(torch.float64), CELLS, EXACT)
    assert placed < 1e-5
    return masses.reshape(-1), placed


def _cells(points: np.ndarray) -> np.ndarray:
    """Each point's cell of the grid, row-major, row 0 at the top as in `cylinder_measure` (all in the frame)."""
    col, row = np.floor((points[:, 0] + 0.5) * CELLS), np.floor((0.5 - points[:, 1]) * CELLS)
    assert ((col >= 0) & (col < CELLS) & (row >= 0) & (row < CELLS)).all()
    return (row * CELLS + col).astype(np.int64)


def _pooled(expected: np.ndarray, least: float) -> np.ndarray:
    """Which bin each cell counts in: its own if ``expected`` there is at least ``least``, else one shared bin
    (itself folded into the smallest kept bin when still under ``least``)."""
    kept = np.flatnonzero(expected >= least)
    bins = np.full(len(expected), len(kept))
    bins[kept] = np.arange(len(kept))
    if expected[expected < least].sum() < least:
        bins[bins == len(kept)] = int(np.argmin(expected[kept]))
    return bins


@pytest.mark.parametrize("name", sorted(FAIR))
def test_two_thousand_chaos_game_points_are_independent_draws_of_the_measure(name):
    """At n = 2000 (<= CHAINS) each point ends its own chain, past its burn-in: the cell counts are multinomial
    with the exact masses (within 1e-6, a 0.002 count), so Pearson's chi-square, over cells pooled to at least 5
    expected points, stays below its 1 - ALPHA quantile (uniform p-values over 300 seeds, measured)."""
    n = 2000
    exact, _ = _exact(name)
    bins = _pooled(n * exact, 5)
    expected = np.bincount(bins, n * exact)
    observed = np.bincount(bins[_cells(chaos_game(FAIR[name](), n, seed=1))], minlength=len(expected))
    chi2 = ((observed - expected) ** 2 / expected).sum()
    assert chi2 < stats.chi2.ppf(1 - ALPHA, len(expected) - 1)


@pytest.mark.parametrize("name", sorted(FAIR))
def test_a_million_chaos_game_points_match_the_measure_within_the_noise_of_their_chains(name):
    """At n = 10^6 each of the CHAINS chains records its next points: draws of the measure, but a chain's are not
    independent of one another, while the chains are (row i is chain i % CHAINS's). So each cell's noise is measured
    between 64 groups of chains (batch means): the gap of its count to n times its mass, less n times the mass the
    cylinders placed (their bound on the exact mass), is within Student's t (63 degrees of freedom) at a false
    alarm of ALPHA shared among the cells, pooled to 1000 expected points each (Bonferroni)."""
    n, groups = 10 ** 6, 64
    exact, placed = _exact(name)
    bins = _pooled(n * exact, 1000)
    mass = np.bincount(bins, exact)
    group = np.arange(n) % CHAINS % groups
    counts = np.bincount(group * len(mass) + bins[_cells(chaos_game(FAIR[name](), n, seed=2))],
                         minlength=groups * len(mass)).reshape(groups, len(mass))
    gap = counts - counts.sum(1, keepdims=True) * mass  # (groups, bins): each group's count less its expectation
    spread = gap.std(0, ddof=1) / np.sqrt(groups)
    t = np.maximum(np.abs(gap.mean(0)) - n * placed / groups, 0) / spread
    assert t.max() < stats.t.ppf(1 - ALPHA / (2 * len(mass)), groups - 1)


@pytest.mark.parametrize("name", sorted(FAIR))
def test_two_thousand_chaos_game_points_are_two_thousand_distinct_points(name):
    """Each point ends its own chain after `burn_in_steps` steps: two coincide only where their chains chose the
    same last maps to float64's precision (34 of the Koch curve's, about 52 of the others', whose scale is 1/2), a
    chance below (2000 choose 2) (sum_i p_i^2)^k: 1e-14 for the Koch curve, 5e-10 for the halvings, 3e-16 for the
    lopsided triangle. So the 2000 points are 2000 distinct points."""
    assert len(np.unique(chaos_game(FAIR[name](), 2000), axis=0)) == 2000


@pytest.mark.parametrize("name", ["koch", "halves", "fern"])
def test_after_its_burn_in_a_chain_has_forgotten_its_start(name):
    """The same `burn_in_steps` random maps applied to the attractor's two farthest fixed points end within
    float64's resolution of each other (a few units in the last place)."""
    ifs = patterns.fern() if name == "fern" else FAIR[name]()
    maps = ifs.to(torch.float64).maps().detach()
    steps = burn_in_steps(maps)
    lin, shift = maps[:, :2, :2].numpy(), maps[:, :2, 2].numpy()
    fixed = np.stack([np.linalg.solve(np.eye(2) - a, t) for a, t in zip(lin, shift)])
    far = np.linalg.norm(fixed[:, None] - fixed[None], axis=-1)
    ends = fixed[list(np.unravel_index(far.argmax(), far.shape))]
    for pick in np.random.default_rng(0).integers(len(maps), size=steps):
        ends = ends @ lin[pick].T + shift[pick]
    assert np.abs(ends[0] - ends[1]).max() <= 8 * np.finfo(np.float64).eps * max(1.0, np.abs(ends).max())
    assert steps == {"koch": 34, "halves": 53, "fern": 227}[name]


def test_the_chaos_game_is_seeded_and_the_same_at_one_and_two_threads():
    """numpy draws and walks the chains, on one thread whatever torch's count; torch only builds the maps."""
    fern, before = patterns.fern(), torch.get_num_threads()
    try:
        torch.set_num_threads(1)
        one = chaos_game(fern, 30_000, seed=5)
        torch.set_num_threads(2)
        two = chaos_game(fern, 30_000, seed=5)
    finally:
        torch.set_num_threads(before)
    assert one.shape == (30_000, 2) and one.dtype == np.float64
    assert np.array_equal(one, two)
    assert not np.array_equal(one, chaos_game(fern, 30_000, seed=6))


@pytest.mark.parametrize("n, maps, message", [
    (0, None, "integer >= 1"), (-5, None, "integer >= 1"), (2.5, None, "integer >= 1"),
    (100, [[[1.0, 0, 0], [0, 0.5, 0]], [[0.5, 0, 0.1], [0, 0.5, 0]]], "rule 0 .* not contractive"),
    (100, [[[0.5, 0, 0], [0, 0.5, 0]], [[0.9, 0.6, 0], [0, 0.5, 0]]], "rule 1 .* not contractive"),
])
def test_the_chaos_game_refuses_bad_input(n, maps, message):
    """A map of scale 1 or more has no attractor: refused at once rather than walked."""
    ifs = patterns.koch() if maps is None else patterns.affine(maps)
    with pytest.raises(ifslib.IFSError, match=message):
        chaos_game(ifs, n)


def test_maps_too_slow_to_forget_the_start_are_warned_of_and_still_drawn_on_the_attractor():
    """A map of scale 0.99999 would need 3.6 million steps to forget the chains' start: the chains take
    MAX_BURN_IN, say so, and their points still lie on the attractor: the segment [0, 0.2] of the x axis
    (x -> 0.99999 x and x -> x / 2 + 0.1 on it; y -> y / 2 squashes the rest onto it)."""
    ifs = patterns.affine([[[0.99999, 0, 0], [0, 0.5, 0]], [[0.5, 0, 0.1], [0, 0.5, 0]]])
    with pytest.warns(UserWarning, match="not a fair sample") as said:
        points = chaos_game(ifs, 1000)
    assert said[0].filename == __file__  # the warning names the caller's line, not the library's
    assert np.abs(points[:, 1]).max() < 1e-12
    assert points[:, 0].min() >= -1e-12 and points[:, 0].max() <= 0.2 + 1e-12
