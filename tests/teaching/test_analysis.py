"""Self-crossings, gradient fields, copy outlines, byte-stable figures, and the new patterns."""
import math

import numpy as np
import pytest
import torch

import ifslib
from ifslib import figures, landscape, metrics
from ifslib.core.geometry.crossings import is_curve


def polyline_ifs(points):
    """An IFS whose depth-0 figure is the polyline through ``points`` (one segment primitive each)."""
    n = len(points)
    rules = [{"kind": "segment", "from": [0, 1], "to": [0, 1]}]  # unused at depth 0
    prims = [{"kind": "segment", "points": [i, i + 1]} for i in range(n - 1)]
    return ifslib.IFS(points, rules, prims, depth=0)


def brute_crossings(seg):
    """Count proper crossings by solving each pair's 2x2 system: 0 < t, u < 1."""
    count = 0
    for i in range(len(seg)):
        for j in range(i + 1, len(seg)):
            (a, b), (c, d) = seg[i], seg[j]
            m = np.array([b - a, c - d]).T
            if abs(np.linalg.det(m)) < 1e-12:
                continue
            t, u = np.linalg.solve(m, c - a)
            count += 1e-6 < t < 1 - 1e-6 and 1e-6 < u < 1 - 1e-6  # float32 vertices meet to ~1e-7
    return count


def test_koch_has_no_self_crossings_at_any_depth():
    for depth in range(1, 5):
        assert metrics.self_crossings(ifslib.patterns.koch(depth=depth)) == 0


def test_self_crossings_count_a_bow_tie_and_ignore_touching():
    bow = polyline_ifs([[-0.3, -0.3], [0.3, 0.3], [0.3, -0.3], [-0.3, 0.3]])
    assert metrics.self_crossings(bow) == 1
    touching = polyline_ifs([[-0.3, 0.0], [0.0, 0.0], [0.0, 0.3], [-0.1, 0.0]])  # ends on the first segment
    assert metrics.self_crossings(touching) == 0


@pytest.mark.parametrize("seed", range(4))
def test_self_crossings_match_brute_force_on_folded_koch_curves(seed):
    ifs = ifslib.patterns.koch_paper(seed, depth=2)
    seg = metrics.curve_segments(ifs)
    assert seg.shape == (16 * 4, 2, 2)
    assert metrics.self_crossings(ifs) == brute_crossings(seg)


def test_crossing_penalty_is_zero_without_crossings_and_the_depth_of_a_bow_tie():
    from ifslib.core.geometry.crossings import crossing_penalty

    assert crossing_penalty(ifslib.patterns.koch(depth=3)).item() == 0
    bow = polyline_ifs([[-0.3, -0.3], [0.3, 0.3], [0.3, -0.3], [-0.1, 0.3]]).to(torch.float64)
    # segments 0 and 2 cross; the shallowest way out moves (-0.1, 0.3) onto the line y = x
    assert crossing_penalty(bow).item() == pytest.approx(0.4 / math.sqrt(2), rel=1e-6)  # float32 corners


@pytest.mark.parametrize("seed", [2, 8])
def test_crossing_penalty_gradient_matches_finite_differences(seed):
    from conftest import perturbed
    from ifslib.core.geometry.crossings import crossing_penalty

    ifs = perturbed(ifslib.patterns.koch(depth=2), 0.2, seed=seed)  # float64, jittered enough to cross itself
    value = crossing_penalty(ifs)
    assert value.item() > 0.01
    value.backward()
    eps, pts = 1e-7, ifs.points.detach()
    for i, j in [(1, 0), (2, 1), (3, 0)]:
        up, down = pts.clone(), pts.clone()
        up[i, j] += eps
        down[i, j] -= eps
        fd = (crossing_penalty(ifs.clone(up)) - crossing_penalty(ifs.clone(down))).item() / (2 * eps)
        assert ifs.points.grad[i, j].item() == pytest.approx(fd, rel=1e-5, abs=1e-8)


def test_self_crossings_need_segment_primitives():
    with pytest.raises(ifslib.IFSError, match="segments"):
        metrics.self_crossings(ifslib.patterns.sierpinski_carpet(depth=1))


def test_gradient_field_equals_finite_differences():
    ifs = ifslib.patterns.koch(depth=2).to(torch.float64)
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 32)
    x, y = 0.03, 0.2
    field = landscape.gradient_field(ifs, target, 2, np.array([x]), np.array([y]), "multiscale_distance", progress=False)

    def value(px, py):
        pts = ifs.points.detach().clone()
        pts[2] = torch.tensor([px, py], dtype=torch.float64)
        with torch.no_grad():
            return float(ifslib.loss(ifslib.distance_field(ifs.clone(pts), 32), target, "multiscale_distance"))

    h = 1e-6
    fd = [(value(x + h, y) - value(x - h, y)) / (2 * h), (value(x, y + h) - value(x, y - h)) / (2 * h)]
    np.testing.assert_allclose(field[0, 0], -np.array(fd), rtol=1e-4, atol=1e-9)


def test_alignment_of_known_fields():
    d = landscape.toward(np.array([-1.0, 0.0, 1.0]), np.array([0.0]), (0.0, 0.0))
    assert np.allclose(d[0], [[1, 0], [0, 0], [-1, 0]])
    assert landscape.alignment(d, d) == (1.0, 1.0)
    assert landscape.alignment(-d, d) == (-1.0, 0.0)
    assert all(math.isnan(v) for v in landscape.alignment(np.zeros((2, 2)), d[0, :2]))


def test_gradient_field_rejects_a_bad_index():
    target = ifslib.load_target(ifslib.patterns.koch(depth=1), 16)
    with pytest.raises(ifslib.IFSError, match="out of range"):
        landscape.gradient_field(ifslib.patterns.koch(depth=1), target, 9, np.zeros(1), np.zeros(1), "pixel",
                                 progress=False)


def test_copy_outlines_are_the_maps_of_the_bounding_box():
    koch = ifslib.patterns.koch(depth=2)
    quads = figures.copy_outlines(koch, 2, size=256)
    assert quads.shape == (4, 5, 2)
    assert np.allclose(quads[:, 0], quads[:, 4])
    # The first copy is the whole depth-1 figure's box shrunk by 1/3 towards p0.
    box_width = quads[0, 1, 0] - quads[0, 0, 0]
    assert box_width == pytest.approx((0.8 + 1 / 256) / 3, abs=2 / 256)


def test_save_figure_is_byte_stable_and_unstamped(tmp_path, monkeypatch):
    fig = figures.gallery([[np.eye(8), np.ones((8, 8))]], ["a", "b"])
    first = figures.save_figure(fig, "f", tmp_path / "one")
    second = figures.save_figure(fig, "f", tmp_path / "two")
    assert first.read_bytes() == second.read_bytes()
    assert b"Software" not in first.read_bytes() and b"matplotlib" not in first.read_bytes()
    monkeypatch.delenv(figures.FIGURES_ENV, raising=False)
    assert figures.save_figure(fig, "f", "") is None
    # an empty folder falls back on IFSLIB_FIGURES (how the tests collect nbval's figures); a given one wins
    monkeypatch.setenv(figures.FIGURES_ENV, str(tmp_path / "env"))
    assert figures.save_figure(fig, "f", "") == tmp_path / "env" / "f.png"
    assert figures.save_figure(fig, "g", tmp_path / "one") == tmp_path / "one" / "g.png"
    assert not (tmp_path / "env" / "g.png").exists()


def test_koch_paper_is_the_papers_start():
    a, b = ifslib.patterns.koch_paper(3), ifslib.patterns.koch_paper(3)
    assert torch.equal(a.points, b.points)
    pts = a.points.detach().numpy()
    assert np.all(np.abs(pts[:, 0] - 0.05) <= 0.1 + 1e-6)
    assert np.all(np.abs(pts[:, 1] - np.linspace(0.4, -0.4, 5)) <= 0.1 + 1e-6)
    assert [p.points for p in a.primitives] == [(0, 1), (1, 2), (2, 3), (3, 4)]
    assert not torch.equal(a.points, ifslib.patterns.koch_paper(4).points)


def test_rosette_is_six_fold_and_contractive():
    ros = ifslib.patterns.by_name("rosette6", depth=2)
    assert len(ros.rules) == 6
    assert np.allclose(ros.scales().numpy(), 0.35 / 0.4)
    image = ifslib.render(ros, 64).detach().numpy()
    assert np.allclose(image, np.rot90(image, 2), atol=0.05)  # six-fold includes the half turn


def test_curves_are_recognized():
    assert is_curve(ifslib.patterns.koch()) and is_curve(ifslib.patterns.koch_paper(0))
    assert not is_curve(ifslib.patterns.rosette(6)) and not is_curve(ifslib.patterns.grid(3))


def test_crossing_points_lie_on_both_segments():
    bow = polyline_ifs([[-0.3, -0.3], [0.3, 0.3], [0.3, -0.3], [-0.1, 0.1]])
    pts = metrics.crossing_points(bow)
    assert pts.shape == (1, 2) and np.allclose(pts[0], [0.0, 0.0])
    assert metrics.crossing_points(ifslib.patterns.koch(depth=3)).shape == (0, 2)


def test_caption_judges_curves_by_chamfer_and_shapes_by_iou():
    koch = ifslib.patterns.koch()
    target = ifslib.load_target(koch, 64)
    assert ifslib.metrics.caption(koch, target) == "Chamfer 0.00 px"
    carpet = ifslib.patterns.sierpinski_carpet(depth=2)
    assert ifslib.metrics.caption(carpet, ifslib.load_target(carpet, 64)) == "IoU 1.00"
