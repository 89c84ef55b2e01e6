"""Rule maps: the paper's Eq. (1) with its erratum, square rules, gradient modes, bad rules."""
import math

import pytest
import torch

import ifslib
from ifslib.core.geometry.rules import map_scales

R3 = math.sqrt(3)


def paper_koch_points():
    # The paper's base segment runs from (0, 0) to (1, 0). Its text says "(0, 0) and (0, 1)": an
    # erratum, since its own T4 translates by (2/3, 0), along x.
    return [[0, 0], [1 / 3, 0], [1 / 2, R3 / 6], [2 / 3, 0], [1, 0]]


def test_eq1_koch_maps_match_paper_with_t3_erratum():
    ifs = ifslib.IFS(paper_koch_points(), ifslib.patterns.koch().rules, ifslib.patterns.koch().primitives,
                     dtype=torch.float64)
    maps = ifs.maps().detach()
    t1 = [[1 / 3, 0, 0], [0, 1 / 3, 0], [0, 0, 1]]
    t2 = [[1 / 6, -R3 / 6, 1 / 3], [R3 / 6, 1 / 6, 0], [0, 0, 1]]
    t3_printed = [[1 / 6, R3 / 6, 1 / 3], [-R3 / 6, 1 / 6, 0], [0, 0, 1]]
    # Erratum: T3 must translate by (1/2, sqrt(3)/6), the peak p2, not the printed (1/3, 0).
    t3_correct = [[1 / 6, R3 / 6, 1 / 2], [-R3 / 6, 1 / 6, R3 / 6], [0, 0, 1]]
    t4 = [[1 / 3, 0, 2 / 3], [0, 1 / 3, 0], [0, 0, 1]]
    for got, want in zip(maps, [t1, t2, t3_correct, t4]):
        torch.testing.assert_close(got, torch.tensor(want, dtype=torch.float64))
    assert not torch.allclose(maps[2], torch.tensor(t3_printed, dtype=torch.float64))
    # the printed T3 does not even map the segment's start onto p2
    assert torch.tensor(t3_printed, dtype=torch.float64)[:2, 2].tolist() != [0.5, R3 / 6]


def test_segment_rule_maps_endpoints_and_is_a_similarity():
    g = torch.Generator().manual_seed(1)
    pts = torch.rand(4, 2, generator=g, dtype=torch.float64) - 0.5
    ifs = ifslib.IFS(pts, [{"kind": "segment", "from": [0, 1], "to": [2, 3]}], [{"kind": "segment", "points": [0, 1]}],
                     depth=0, dtype=torch.float64)
    t = ifs.maps()[0].detach()
    for a, b in [(0, 2), (1, 3)]:
        torch.testing.assert_close(t[:2, :2] @ pts[a] + t[:2, 2], pts[b])
    a = t[:2, :2]
    s = map_scales(t)
    torch.testing.assert_close(a.T @ a, s ** 2 * torch.eye(2, dtype=torch.float64))  # rotation x scale
    assert torch.det(a) > 0  # no reflection


def test_square_rule_scale_and_lower_left_corner():
    pts = [[-0.4, -0.4], [0.4, 0.4], [0.2, 0.1], [0.0, -0.1]]  # second square given upper-right first
    ifs = ifslib.IFS(pts, [{"kind": "square", "from": [0, 1], "to": [2, 3]}], [{"kind": "box", "points": [0, 1]}],
                     depth=1, dtype=torch.float64)
    t = ifs.maps()[0].detach()
    assert t[0, 1] == 0 and t[1, 0] == 0
    assert t[0, 0].item() == pytest.approx(math.hypot(0.2, 0.2) / math.hypot(0.8, 0.8))
    ll = t[:2, :2] @ torch.tensor([-0.4, -0.4], dtype=torch.float64) + t[:2, 2]
    torch.testing.assert_close(ll, torch.tensor([0.0, -0.1], dtype=torch.float64))


def test_paper_gradient_mode_same_value_cut_rotation_gradient():
    ifs = ifslib.patterns.koch().to(torch.float64)
    exact, paper = ifs.maps("exact"), ifs.maps("paper")
    torch.testing.assert_close(exact, paper)
    g_exact = torch.autograd.grad(exact[1, 0, 1], ifs.points)[0]  # -sin(theta) * scale of rule 1
    g_paper = torch.autograd.grad(paper[1, 0, 1], ifs.points)[0]
    assert not torch.allclose(g_exact, g_paper)
    # square rules have no rotation: both modes agree, gradients included
    carpet = ifslib.patterns.sierpinski_carpet().to(torch.float64)
    ge = torch.autograd.grad(carpet.maps("exact").sum(), carpet.points)[0]
    gp = torch.autograd.grad(carpet.maps("paper").sum(), carpet.points)[0]
    torch.testing.assert_close(ge, gp)


def test_unknown_gradient_mode():
    with pytest.raises(ValueError, match="unknown gradient mode 'approx'"):
        ifslib.patterns.koch().maps("approx")


def test_zero_length_rule_segment_is_a_clear_error():
    ifs = ifslib.patterns.koch()
    with torch.no_grad():
        ifs.points[4] = ifs.points[0]
    with pytest.raises(ValueError, match=r"rule 0 \(segment\): its source segment from point 0 to point 4 has zero length"):
        ifs.maps()


def test_non_contractive_rule_at_positive_depth():
    pts = [[-0.1, 0], [0.1, 0], [-0.4, 0], [0.4, 0]]
    ifs = ifslib.IFS(pts, [{"kind": "segment", "from": [0, 1], "to": [2, 3]}], [{"kind": "segment", "points": [0, 1]}], depth=2)
    with pytest.raises(ValueError, match=r"rule 0 \(segment\) is not contractive: its scale is 4 >= 1"):
        ifslib.distance_field(ifs, 8)
    assert ifslib.distance_field(ifs, 8, depth=0).shape == (8, 8)  # depth 0 needs no contraction


def test_koch_unit_is_eq1_frame():
    unit = ifslib.patterns.koch_unit()
    torch.testing.assert_close(unit.points.detach(), torch.tensor(paper_koch_points(), dtype=torch.float64))
