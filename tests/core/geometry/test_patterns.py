"""patterns.koch_like: a self-similar curve from any polyline, with the Koch curve's rules."""
import math

import numpy as np
import pytest
import torch

import ifslib
from ifslib.core.geometry.patterns import conjugated, koch, koch_like
from ifslib.core.geometry.random_fractals import random_affine


def koch_points(width=0.8):
    w = width
    return [[-w / 2, 0.0], [-w / 6, 0.0], [0.0, w * math.sqrt(3) / 6], [w / 6, 0.0], [w / 2, 0.0]]


def test_koch_points_give_the_koch_curve():
    ours, theirs = koch_like(koch_points(), depth=3), koch(depth=3)
    assert ours.rules == theirs.rules
    assert ours.primitives == theirs.primitives
    assert torch.allclose(ours.points, theirs.points)
    assert torch.allclose(ours.maps(), theirs.maps(), atol=1e-6)
    assert torch.allclose(ifslib.render(ours, 48), ifslib.render(theirs, 48), atol=1e-5)


def test_any_polyline_makes_one_rule_per_segment():
    points = [[-0.4, 0.0], [-0.1, 0.1], [0.1, -0.1], [0.4, 0.0]]  # three segments: an S
    ifs = koch_like(points, depth=2, radius=0.01, name="s")
    assert [(r.kind, r.source, r.target) for r in ifs.rules] == [("segment", (0, 3), (i, i + 1)) for i in range(3)]
    assert ifs.primitives[0].points == (0, 3) and ifs.primitives[0].radius == 0.01
    assert ifs.depth == 2 and ifs.name == "s"
    base = math.dist(points[0], points[-1])
    expected = [math.dist(points[i], points[i + 1]) / base for i in range(3)]
    assert np.allclose(ifs.scales().numpy(), expected, atol=1e-6)
    # a tensor with grad is accepted too
    again = koch_like(ifs.points, depth=2)
    assert torch.equal(again.points, ifs.points.detach())


def test_the_attractor_is_clean_for_a_flat_peak():
    ifs = koch_like([[-0.4, 0.0], [-0.16, 0.0], [0.0, 0.18], [0.16, 0.0], [0.4, 0.0]], depth=4)
    assert ifslib.metrics.self_crossings(ifs) == 0


@pytest.mark.parametrize("points, words", [
    ([[-0.4, 0.0], [-0.3, 0.9], [0.4, 0.0]], "segment 0 .* length 0.9055"),  # longer than the base: not contractive
    ([[-0.4, 0.0], [0.4, 0.0], [0.4, 0.0], [0.5, 0.0]], "segment 1 .* length 0"),  # collapses to a point
    ([[-0.4, 0.0], [0.0, 0.3], [-0.4, 0.0]], "first and last points coincide"),
    ([[-0.4, 0.0], [0.4, 0.0]], r"n >= 3"),
    ([[-0.4, 0.0, 1.0], [0.0, 0.3, 1.0], [0.4, 0.0, 1.0]], r"\(n, 2\)"),
    ([[-0.4, 0.0], [0.0, float("nan")], [0.4, 0.0]], "not finite"),
])
def test_a_bad_polyline_is_rejected_with_a_clear_value_error(points, words):
    with pytest.raises(ValueError, match=words):
        koch_like(points)


def test_a_conjugated_map_fixes_the_image_of_the_fixed_point():
    # S w S^-1 fixes S(p) when w fixes p: the attractor of the conjugated maps is S of theirs
    maps = random_affine(4, np.random.default_rng(3))
    k, b = 0.6, np.array([0.1, -0.2])

    def fixed(m):
        return np.linalg.solve(np.eye(2) - m[:, :2], m[:, 2])

    for before, after in zip(maps, conjugated(maps, k, b)):
        assert np.allclose(fixed(after), k * fixed(before) + b, atol=1e-12)
        assert np.array_equal(after[:, :2], before[:, :2])
