"""Affine rules: the map from three points onto three, singular values, exact distances under shear and
reflection (against formulas in the plane), the disk's bound, exact gradients, guard rails, the JSON file."""
import pytest
import torch

import ifslib
from ifslib.core.geometry.rules import singular_values

from common_testing import random_affine as _random_affine
from conftest import sheared, sheared_mixed


@pytest.mark.parametrize("seed", range(6))
def test_affine_rule_maps_the_triangle_vertex_to_vertex(seed):
    g = torch.Generator().manual_seed(100 + seed)
    pts = torch.rand(6, 2, generator=g, dtype=torch.float64) - 0.5
    ifs = ifslib.IFS(pts, [{"kind": "affine", "from": [0, 1, 2], "to": [3, 4, 5]}], [{"kind": "segment", "points": [0, 1]}],
                     depth=0, dtype=torch.float64)
    t = ifs.maps()[0].detach()
    for i in range(3):
        got = t[:2, :2] @ pts[i] + t[:2, 2]
        torch.testing.assert_close(got, pts[3 + i])


@pytest.mark.parametrize("seed", range(6))
def test_singular_values_match_svd(seed):
    a, _ = _random_affine(seed, reflect=seed % 2 == 1)
    m = torch.eye(3, dtype=torch.float64)
    m[:2, :2] = a
    lo, hi = singular_values(m)
    want = torch.linalg.svdvals(a)
    torch.testing.assert_close(torch.stack([hi, lo]), want)


def test_an_affine_rule_that_is_a_similarity_draws_the_koch_curve():
    """Koch's four maps written as affine rules give the segment rules' field, value for value."""
    koch = ifslib.patterns.koch(depth=3).to(torch.float64)
    maps = koch.maps().detach()
    same = ifslib.patterns.affine(maps, depth=3, primitive="segment", dtype=torch.float64)
    # the segment primitive of `affine` is the frame's bottom side; draw Koch's base segment instead
    pts = torch.cat([same.points.detach(), koch.points.detach()[[0, 4]]])
    n = pts.shape[0]
    same = ifslib.IFS(pts, same.rules, [{"kind": "segment", "points": [n - 2, n - 1]}], depth=3, dtype=torch.float64)
    torch.testing.assert_close(same.maps().detach(), maps)
    torch.testing.assert_close(ifslib.distance_field(same, 48), ifslib.distance_field(koch, 48), rtol=0, atol=1e-12)


@pytest.mark.parametrize("make", [sheared, sheared_mixed], ids=["box", "mixed"])
def test_affine_gradient_matches_finite_differences(make):
    ifs = make(depth=2)
    free = [i for i in range(ifs.n_points) if i not in ifs.fixed]

    def field(free_points):
        pts = ifs.points.detach().clone()
        pts[free] = free_points
        work = ifs.clone()
        work.points = pts
        d = ifslib.distance_field(work, 12, 2, dtype=torch.float64)
        return torch.relu(d) + 0.5 * d

    start = ifs.points.detach()[free].clone().requires_grad_(True)
    assert torch.autograd.gradcheck(field, (start,), eps=1e-7, atol=1e-5, rtol=1e-4)


def test_contraction_is_the_largest_singular_value():
    # det = 0.36 * 1.2 = 0.43 (sqrt 0.66 < 1) but it stretches x by 1.2: not contractive
    stretch = ifslib.patterns.affine([[[1.2, 0.0, 0.0], [0.0, 0.36, 0.0]]], depth=2)
    with pytest.raises(ValueError, match=r"rule 0 \(affine\) is not contractive: its scale is 1\.2 >= 1"):
        ifslib.distance_field(stretch, 8)
    assert ifslib.distance_field(stretch, 8, depth=0).shape == (8, 8)  # depth 0 needs no attractor
    torch.testing.assert_close(sheared().scales(), torch.linalg.svdvals(sheared().maps().detach()[:, :2, :2])[:, 0])


def test_degenerate_maps_and_bad_affine_rules_are_clear_errors():
    flat = ifslib.patterns.affine([[[0.5, 0.0, 0.0], [0.25, 0.0, 0.0]]], depth=1)  # rank 1: a line
    with pytest.raises(ValueError, match=r"rule 0 \(affine\) is degenerate: its smallest singular value is"):
        ifslib.distance_field(flat, 8)
    with pytest.raises(ValueError, match="has zero area"):
        ifslib.IFS([[0, 0], [1, 1], [2, 2], [0, 1]], [{"kind": "affine", "from": [0, 1, 2], "to": [0, 1, 3]}],
                   [{"kind": "segment", "points": [0, 1]}]).maps()
    with pytest.raises(ValueError, match=r"an affine rule's 'from' must be 3 point indices, got \[0, 1\]"):
        ifslib.IFS([[0, 0], [1, 0], [0, 1]], [{"kind": "affine", "from": [0, 1], "to": [0, 1, 2]}],
                   [{"kind": "segment", "points": [0, 1]}])
    with pytest.raises(ValueError, match="maps must have shape"):
        ifslib.patterns.affine([[1.0, 0.0]])
    with pytest.raises(ValueError, match="draws a 'box' or a 'segment'"):
        ifslib.patterns.affine([[[0.5, 0, 0], [0, 0.5, 0]]], primitive="disk")


def test_affine_ifs_round_trips_through_json(tmp_path):
    ifs = sheared_mixed(depth=3)
    path = ifslib.save_ifs(ifs, tmp_path / "sheared.json")
    back = ifslib.load_ifs(path)
    assert back.rules == ifs.rules and back.primitives == ifs.primitives and back.fixed == ifs.fixed
    assert [r.source + r.target for r in back.rules][0] == (0, 1, 2, 4, 5, 6)
    torch.testing.assert_close(ifslib.distance_field(back.to(torch.float64), 24), ifslib.distance_field(ifs, 24))


def test_a_short_fit_of_affine_maps_moves_only_the_free_points():
    target = ifslib.load_target(sheared(depth=2), 32)
    start = ifslib.patterns.affine([[[0.45, 0.0, -0.2], [0.0, 0.45, -0.2]], [[0.45, 0.0, 0.2], [0.0, 0.45, -0.2]],
                                    [[0.45, 0.0, 0.0], [0.0, 0.45, 0.2]]], depth=2)
    result = ifslib.fit(start, target, steps=40, lr=0.01, loss="multiscale_distance", strategy="plain", progress=False)
    assert result.best_loss < result.history.loss[0] * 0.7
    assert torch.equal(result.best.points.detach()[:4], start.points.detach()[:4])


def test_cli_info_shows_both_singular_values_and_reflections(tmp_path, capsys):
    from ifslib.cli import main

    path = ifslib.save_ifs(sheared(), tmp_path / "sheared.json")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "rule 0: affine [0, 1, 2] -> [4, 5, 6]  contraction 0.4758 (singular values 0.4758, 0.2837)" in out
    assert "rule 2: affine [0, 1, 2] -> [10, 11, 12]  contraction 0.4178 (singular values 0.4178, 0.3471, reflects)" in out
