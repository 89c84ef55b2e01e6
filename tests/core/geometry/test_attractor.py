"""The attractor: its depth-free distance against the float64 chaos game, the KD-tree search against brute
force, gradients against finite differences, the window, and bad inputs (through the CLI too)."""
import functools
import math

import numpy as np
import pytest
import torch
from scipy.spatial import cKDTree

import ifslib
import ifslib.cli
from ifslib.core.geometry.attractor import attractor_ball, leaf_points
from ifslib.core.geometry.expand import expand_attractor
from ifslib.core.raster.chaos import chaos_field, chaos_game
from ifslib.core.raster.distance import Budget, distance_field

from conftest import PATTERNS, perturbed

SIZE = 48


def _stem_zero():
    """Barnsley's fern with the classic stem: a singular value exactly 0 (no inverse at all)."""
    maps = list(ifslib.patterns.FERN_MAPS)
    maps[0] = ((0.0, 0.0, 0.0), (0.0, 0.16, 0.0))
    return ifslib.patterns.fern(maps=maps, name="fern0")


ATTRACTORS = {**PATTERNS,
              "fern": lambda: ifslib.patterns.fern(),
              "fern_singular": _stem_zero,
              "reflection": lambda: ifslib.patterns.affine([[[-0.5, 0.0, 0.2], [0.0, 0.5, 0.1]],
                                                            [[0.3, 0.25, -0.2], [-0.2, -0.4, -0.15]],
                                                            [[0.45, -0.1, 0.05], [0.05, 0.05, 0.3]]])}

#: How far the chaos game's points (1M, float64) may fall short of covering the attractor, in pixels at 48²
#: (measured: at most 0.1 px on these patterns).
COVERAGE = 0.25


@functools.lru_cache(maxsize=None)
def _chaos(name):
    """The float64 chaos game's distance field of a test attractor, in pixels at SIZE (one per pattern)."""
    return chaos_field(ATTRACTORS[name]().to(torch.float64), SIZE, 1_000_000, seed=1) * SIZE


@pytest.fixture(params=sorted(ATTRACTORS))
def attractor_name(request):
    return request.param


@pytest.mark.parametrize("tolerance", [0.5, 0.2])
def test_field_is_within_tolerance_of_the_chaos_game(attractor_name, tolerance):
    """d(x, A) - ε <= field <= d(x, A) + ε, against the float64 chaos game (whose points all lie on A).

    Since the chaos points lie on A, d(x, points) >= d(x, A): so field <= d(x, points) + ε must hold
    exactly, and field >= d(x, points) - ε - coverage, the coverage being how far 1M points fall short."""
    ifs = ATTRACTORS[attractor_name]().to(torch.float64)
    field = distance_field(ifs, SIZE, "attractor", tolerance=tolerance).detach() * SIZE  # in pixels
    chaos = _chaos(attractor_name)
    assert (field <= chaos + tolerance + 1e-9).all(), (field - chaos).max()
    assert (field >= chaos - tolerance - COVERAGE).all(), (chaos - field).max()


def test_kd_tree_search_equals_brute_force(attractor_name):
    ifs = ATTRACTORS[attractor_name]().to(torch.float64)
    fast = distance_field(ifs, 40, "attractor", tolerance=0.3)
    brute = distance_field(ifs, 40, "attractor", tolerance=0.3, method="brute")
    torch.testing.assert_close(fast, brute, rtol=0, atol=1e-12)


def test_every_chaos_point_lies_in_the_ball(attractor_name):
    ifs = ATTRACTORS[attractor_name]().to(torch.float64)
    centre, radius = attractor_ball(ifs.maps().detach())
    points = chaos_game(ifs, 100_000, seed=3)
    assert np.linalg.norm(points - centre.numpy(), axis=1).max() <= radius + 1e-12


def test_branches_are_cut_by_their_own_scale():
    """A branch of scale 0.85 goes much deeper than one of 0.2, and every leaf is within ε."""
    ifs = ifslib.patterns.affine([[[0.85, 0.0, 0.05], [0.0, 0.85, 0.05]], [[0.2, 0.0, -0.3], [0.0, 0.2, -0.3]]],
                                 dtype=torch.float64)
    leaves = expand_attractor(ifs, 1e-3)
    assert (leaves.error <= 1e-3).all()
    length = (leaves.words < 2).sum(1)
    assert length.max() >= 3 * length.min()
    torch.testing.assert_close(leaf_points(leaves, torch.arange(len(leaves))), leaves.points, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["koch", "affine", "fern"])
def test_gradient_matches_finite_differences(name):
    ifs = perturbed(ATTRACTORS[name](), scale=0.01, seed=4)
    base = ifs.points.detach().clone()

    def field(points):
        work = ifs.clone()
        work.points = points
        return distance_field(work, 10, "attractor", dtype=torch.float64)

    assert torch.autograd.gradcheck(field, (base.clone().requires_grad_(True),), eps=1e-7, atol=1e-5, rtol=1e-4)


def test_loss_gradient_of_the_attractor_matches_central_differences():
    """A whole loss (the multiscale distance against a target), not only the field."""
    ifs = perturbed(ifslib.patterns.koch(), scale=0.02, seed=2)
    target = ifslib.load_target(ifslib.render(ifslib.patterns.koch(), 32).detach().numpy() >= 0.5, 32)

    def loss():
        return ifslib.loss(distance_field(ifs, 32, "attractor", dtype=torch.float64), target, "multiscale_distance")

    loss().backward()
    grad = ifs.points.grad.clone()
    fd = torch.zeros_like(grad)
    with torch.no_grad():
        for i in range(ifs.n_points):
            for j in range(2):
                ifs.points[i, j] += 1e-7
                up = loss().item()
                ifs.points[i, j] -= 2e-7
                down = loss().item()
                ifs.points[i, j] += 1e-7
                fd[i, j] = (up - down) / 2e-7
    torch.testing.assert_close(grad, fd, rtol=1e-3, atol=1e-7)


def test_a_window_refines_only_its_own_leaves():
    """64x into the Koch curve: leaves within the window's ε, far fewer than the whole curve at that ε, and the
    field within 2ε of the unpruned leaves' (both are within ε of the attractor)."""
    ifs = ifslib.patterns.koch().to(torch.float64)
    size, zoom = 64, 64
    centre = ifs.points.detach()[1].numpy()  # a vertex of the curve
    half = 0.5 / zoom
    window = (centre[0] - half, centre[1] - half, centre[0] + half, centre[1] + half)
    eps = 0.5 * (2 * half) / size
    pruned = expand_attractor(ifs, eps, window)
    whole = expand_attractor(ifs, eps)
    assert len(pruned) * 20 < len(whole)
    field = distance_field(ifs, size, window=window).detach()
    x, y = ifslib.pixel_centres(size, dtype=torch.float64, window=window)
    # the distance to the nearest unpruned leaf by scipy's exact KD-tree query (a dense cdist is 4096 x every leaf)
    reference = torch.from_numpy(cKDTree(whole.points.numpy()).query(torch.stack([x, y], 1).numpy())[0]).view(size, size)
    assert (field - reference).abs().max() <= 2 * eps + 1e-12
    image = ifslib.render(ifs, size, window=window).detach()
    assert 0.02 < (image >= 0.5).float().mean() < 0.5  # the curve crosses the zoomed window, one pixel wide


def test_render_by_the_chaos_game_is_seeded_and_matches_the_field():
    ifs = ifslib.patterns.fern()
    a = ifslib.render(ifs, 64, method="chaos", points=200_000, seed=5)
    b = ifslib.render(ifs, 64, method="chaos", points=200_000, seed=5)
    assert torch.equal(a, b)
    mask_chaos = a.numpy() >= 0.5
    mask_field = ifslib.render(ifs, 64, "attractor", tolerance=0.1).detach().numpy() >= 0.5
    assert ifslib.iou(mask_chaos, mask_field) > 0.95


def test_bad_inputs_are_clear_errors():
    koch = ifslib.patterns.koch()
    growing = ifslib.patterns.affine([[[1.1, 0.0, 0.0], [0.0, 0.5, 0.0]], [[0.3, 0.0, 0.1], [0.0, 0.3, 0.1]]])
    with pytest.raises(ifslib.IFSError, match=r"rule 0 \(affine\) is not contractive: its scale is 1.1"):
        distance_field(growing, 16, "attractor")
    with pytest.raises(ifslib.IFSError, match="is not contractive"):
        chaos_game(growing, 10)
    with pytest.raises(ifslib.IFSError, match="needs more than 100 leaves"):
        distance_field(koch, 64, "attractor", budget=Budget(leaves=100))
    with pytest.raises(ifslib.IFSError, match="zero or negative size"):
        ifslib.render(koch, 16, window=(0.1, 0.0, 0.1, 0.2))
    with pytest.raises(ifslib.IFSError, match="window must be four numbers"):
        ifslib.render(koch, 16, window=(0.1, 0.2))
    with pytest.raises(ifslib.IFSError, match="chaos-game points must be an integer >= 1"):
        chaos_game(koch, 0)
    with pytest.raises(ifslib.IFSError, match="tolerance must be a finite number of pixels > 0"):
        distance_field(koch, 16, "attractor", tolerance=0)
    with pytest.raises(ifslib.IFSError, match="depth must be an integer >= 0 or 'attractor'"):
        distance_field(koch, 16, "attractors")
    with pytest.raises(ifslib.IFSError, match="use depth='attractor'"):
        distance_field(koch, 16, 3, window=(-0.5, -0.5, 0.5, 0.5))
    with pytest.raises(ifslib.IFSError, match="the chaos game draws the attractor"):
        ifslib.render(koch, 16, 3, method="chaos")


@pytest.mark.parametrize("argv, message", [
    (["--chaos", "0"], "chaos-game points must be an integer >= 1"),
    (["--window", "0", "0", "0", "1"], "zero or negative size"),
    (["--depth", "attractor", "--tolerance", "-1"], "tolerance must be a finite number of pixels > 0"),
])
def test_cli_render_reports_bad_attractor_input(tmp_path, capsys, argv, message):
    code = ifslib.cli.main(["render", "koch", "--size", "16", "-o", str(tmp_path / "a.png")] + argv)
    assert code == 2
    assert message in capsys.readouterr().err


def test_cli_render_reports_a_map_that_does_not_contract(tmp_path, capsys):
    path = tmp_path / "grow.json"
    ifslib.save_ifs(ifslib.patterns.affine([[[1.2, 0.0, 0.0], [0.0, 0.5, 0.0]]]), path)
    assert ifslib.cli.main(["render", str(path), "--depth", "attractor", "-o", str(tmp_path / "a.png")]) == 2
    assert "is not contractive" in capsys.readouterr().err


def test_cli_draws_the_attractor_and_a_zoom(tmp_path, capsys):
    out = tmp_path / "fern.png"
    assert ifslib.cli.main(["render", "fern", "--size", "32", "--depth", "attractor", "-o", str(out)]) == 0
    assert "the attractor (within 0.5 px)" in capsys.readouterr().out
    assert ifslib.cli.main(["render", "fern", "--size", "32", "--window", "-0.05", "-0.05", "0.05", "0.05",
                            "-o", str(out)]) == 0
    assert ifslib.cli.main(["render", "fern", "--size", "32", "--chaos", "20000", "-o", str(out)]) == 0
    assert "chaos game (20,000 points, seed 0)" in capsys.readouterr().out
    assert math.isfinite(out.stat().st_size)


def test_cli_reports_a_leaf_budget_exceeded(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(ifslib.core.geometry.attractor, "DEFAULT_MAX_LEAVES", 1000)
    code = ifslib.cli.main(["render", "carpet", "--size", "64", "--depth", "attractor", "-o", str(tmp_path / "c.png")])
    assert code == 2
    assert "needs more than 1,000 leaves" in capsys.readouterr().err


def test_cli_fit_of_the_attractor_at_every_stage(tmp_path, capsys):
    target = tmp_path / "koch.png"
    assert ifslib.cli.main(["render", "koch", "--size", "48", "--depth", "attractor", "-o", str(target)]) == 0
    out = tmp_path / "fit.json"
    assert ifslib.cli.main(["fit", str(target), "--size", "48", "--depth", "attractor", "--steps", "20", "--quiet",
                            "--strategy", "plain", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "attractor: IoU" in printed and "drawn at depth 3" in printed
    scores = ifslib.load_ifs(out).meta["scores"]
    assert set(scores) == {"depth", "attractor"} and scores["attractor"]["chamfer"] < 3
    assert ifslib.cli.main(["fit", str(target), "--pattern", "auto", "--depth", "attractor", "-o", str(out)]) == 2
    assert "--depth attractor goes with a pattern" in capsys.readouterr().err


def test_a_fit_over_the_leaf_budget_stops_with_the_advice_not_with_rollbacks(monkeypatch):
    monkeypatch.setattr(ifslib.core.geometry.attractor, "DEFAULT_MAX_LEAVES", 500)
    target = ifslib.load_target(ifslib.render(ifslib.patterns.sierpinski_carpet(), 32).detach().numpy() >= 0.5, 32)
    with pytest.raises(ifslib.IFSError, match="method='sampled'"):
        ifslib.fit(ifslib.patterns.sierpinski_carpet(), target, steps=5, depth="attractor", strategy="plain",
                   progress=False)
    result = ifslib.fit(ifslib.patterns.sierpinski_carpet(), target, steps=5, depth="attractor",
                        options=ifslib.RunOptions(method="sampled"), strategy="plain", progress=False)
    assert result.history.cost == 5 and not result.history.rollbacks


def test_sampled_leaves_do_not_depend_on_what_was_sampled_before():
    # The walkers' uniforms are cached per (seed, count) and grown when longer words are needed; growing the
    # cache must keep the uniforms already drawn, or a fit's sampled leaves depend on the fits run before it
    # in the same process (it did: the same fit ended at attractor IoU 0.888 first and 0.940 after).
    from ifslib.core.geometry import sampled

    quick = ifslib.random_fractals.random_ifs(3, 1).maps().detach()
    slow = quick.clone()
    slow[0, :2, :2] *= 0.9 / float(torch.linalg.matrix_norm(slow[0, :2, :2], ord=2))  # longer words
    sampled._UNIFORMS.clear()
    fresh = sampled.sample_attractor(quick, 1e-3, 512)
    grown = sampled.sample_attractor(slow, 1e-3, 512)
    assert grown.words.shape[1] > fresh.words.shape[1]  # the cache was grown for the slow maps' longer words
    again = sampled.sample_attractor(quick, 1e-3, 512)
    assert torch.equal(fresh.words, again.words)
    assert torch.equal(fresh.points, again.points)
