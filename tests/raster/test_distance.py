"""Distance field: the SDF law, fast == brute, exact gradients, the search's exactness, bad inputs."""
import math

import pytest
import torch
from common_testing import point_segment as _point_segment, polygon_sdf as _polygon_sdf

import ifslib
from ifslib.geometry.leaves import Leaves, expand, invert_similarities, sdf_dense, sdf_pairs
from ifslib.geometry.primitives import primitive_params
from ifslib.raster.nearest import nearest_leaf, pixel_centres

from conftest import PATTERNS, mixed, perturbed


@pytest.mark.parametrize("seed", range(5))
def test_sdf_law_for_random_similarities(seed):
    """d_{T(S)}(x) = s * d_S(T^-1 x), checked against distances computed in world coordinates."""
    g = torch.Generator().manual_seed(seed)
    rnd = lambda *shape: torch.rand(*shape, generator=g, dtype=torch.float64) - 0.5  # noqa: E731
    a, b, c, lo, hi = rnd(2), rnd(2), rnd(2), rnd(2) * 0.3, rnd(2) * 0.3 + 0.2
    src, dst = rnd(2, 2), rnd(2, 2) * 0.5  # a random similarity T: src segment -> dst segment
    pts = torch.cat([torch.stack([a, b, c, lo, hi]), src, dst])
    prims = [{"kind": "segment", "points": [0, 1], "radius": 0.02}, {"kind": "disk", "points": [2], "radius": 0.1},
             {"kind": "box", "points": [3, 4]}]
    ifs = ifslib.IFS(pts, [{"kind": "segment", "from": [5, 6], "to": [7, 8]}], prims, depth=0, dtype=torch.float64)
    t = ifs.maps()[0].detach()
    s = math.sqrt(abs(torch.det(t[:2, :2]).item()))
    T = lambda p: t[:2, :2] @ p + t[:2, 2]  # noqa: E731
    x = rnd(20, 2) * 1.5
    # any similarity, expanding ones too: build the one-word leaves straight from the map
    inverse, scale = invert_similarities(ifs.maps())
    leaves = Leaves(inverse, scale, primitive_params(ifs.points, ifs.primitives), ("segment", "disk", "box"))
    got = sdf_dense(leaves, x[:, 0], x[:, 1]).detach()  # (20, 3): one word, three primitives
    box = [torch.stack([lo[0], lo[1]]), torch.stack([hi[0], lo[1]]), torch.stack([hi[0], hi[1]]), torch.stack([lo[0], hi[1]])]
    for i, p in enumerate(x):
        want_seg = _point_segment(p, T(a), T(b)) - s * 0.02
        want_disk = (p - T(c)).norm() - s * 0.1
        want_box = _polygon_sdf(p, [T(q) for q in box])
        torch.testing.assert_close(got[i], torch.stack([want_seg, want_disk, want_box]).to(got.dtype))


def _field_pair(ifs, size, depth, dtype, device="cpu"):
    fast = ifslib.distance_field(ifs, size, depth, dtype=dtype, device=device).detach().cpu()
    brute = ifslib.distance_field(ifs, size, depth, method="brute", dtype=dtype, device=device).detach().cpu()
    return fast, brute


@pytest.mark.parametrize("depth", range(5))
def test_fast_equals_brute_on_every_pattern(pattern_name, depth, device):
    ifs = perturbed(PATTERNS[pattern_name](), seed=depth, dtype=torch.float32)
    size = 37 if depth < 4 else 29  # odd sizes: the quadtree covers a padded power of two
    fast, brute = _field_pair(ifs, size, depth, torch.float32, device)
    assert (fast - brute).abs().max().item() <= 1e-5


def test_points_inside_boxes_and_mixed_sizes_are_exact(device):
    ifs = perturbed(mixed(depth=3), scale=0.02, seed=3)
    fast, brute = _field_pair(ifs, 64, 3, torch.float64, device)
    assert (fast < 0).sum() > 20  # plenty of pixels inside boxes and disks
    torch.testing.assert_close(fast, brute, rtol=0, atol=1e-12)


def test_search_is_exact_when_chunked_and_for_tiny_images():
    ifs = perturbed(ifslib.patterns.koch(), seed=7)
    leaves = expand(ifs, 3)
    x, y = pixel_centres(24)
    want = sdf_dense(leaves, x, y).detach().min(dim=1)
    for max_pairs in (1 << 22, 50):
        got = nearest_leaf(leaves, 24, max_pairs=max_pairs)
        torch.testing.assert_close(got.distance, want.values, rtol=0, atol=0)
    one = nearest_leaf(leaves, 1)
    assert one.leaf.shape == (1,)


def test_warm_started_search_equals_brute_force_along_a_whole_fit(pattern_name):
    # each step's search is capped by the distance to the previous step's winners (the warm start);
    # along 25 Adam steps it must give the brute force's distances and the cold search's winners
    ifs = perturbed(PATTERNS[pattern_name](), seed=11, dtype=torch.float32)
    size, depth = 29, 2
    x, y = pixel_centres(size, dtype=torch.float32)
    opt = torch.optim.Adam([ifs.points], lr=0.01)
    fixed = list(ifs.fixed)
    previous, changed = None, 0
    for _ in range(25):
        opt.zero_grad()
        leaves = expand(ifs, depth)
        cold = nearest_leaf(leaves, size)
        if previous is not None:
            upper = sdf_pairs(leaves.detach(), x, y, previous)
            warm = nearest_leaf(leaves, size, upper=upper)
            brute = sdf_dense(leaves, x, y).detach().min(dim=1).values
            assert torch.equal(warm.leaf, cold.leaf)
            assert (warm.distance - brute).abs().max().item() <= 1e-6
            assert warm.pairs <= cold.pairs
            changed += (cold.leaf != previous).sum().item()
        previous = cold.leaf
        field = sdf_pairs(leaves, x, y, cold.leaf)
        (field - 0.05).square().mean().backward()
        if fixed:
            ifs.points.grad[fixed] = 0
        opt.step()
    assert changed > 0  # the winners did move: the warm start was put to the test


def test_float64_on_request_and_float32_by_default():
    ifs = ifslib.patterns.koch()
    assert ifslib.distance_field(ifs, 8, 1).dtype == torch.float32
    assert ifslib.distance_field(ifs, 8, 1, dtype=torch.float64).dtype == torch.float64


def _scalar(field):
    w = torch.linspace(0.5, 1.5, field.numel(), dtype=field.dtype).view_as(field)
    return (torch.relu(field) * w).sum() + (field * w).square().sum()


@pytest.mark.parametrize("name", ["koch", "carpet", "mixed"])
def test_gradient_matches_finite_differences(name):
    """gradcheck in float64 on the whole field: rotations (segment rules), square rules, every primitive."""
    ifs = perturbed(PATTERNS[name](), scale=0.02, seed=11)
    base = ifs.points.detach().clone()

    assert torch.autograd.gradcheck(lambda p: _field_of(ifs, p), (base.clone().requires_grad_(True),),
                                    eps=1e-7, atol=1e-5, rtol=1e-4)


def _field_of(ifs, points):
    # the distance field as a function of a points tensor (keeps its graph, unlike IFS.clone)
    work = ifs.clone()
    work.points = points
    return ifslib.distance_field(work, 12, 2, dtype=torch.float64)


@pytest.mark.parametrize("name", ["koch", "carpet", "mixed"])
def test_fast_and_brute_gradients_agree(name, device):
    ifs = perturbed(PATTERNS[name](), scale=0.02, seed=5)
    grads = []
    for method in ("fast", "brute"):
        ifs.points.grad = None
        _scalar(ifslib.distance_field(ifs, 40, 3, method=method, dtype=torch.float64, device=device)).backward()
        grads.append(ifs.points.grad.clone())
    torch.testing.assert_close(grads[0], grads[1], rtol=1e-9, atol=1e-9)


def test_paper_gradient_disagrees_with_finite_differences():
    """The paper's cut rotation gradient is wrong; the exact one is right (central differences)."""
    ifs = perturbed(ifslib.patterns.koch(), scale=0.03, seed=2)
    loss = lambda mode: _scalar(ifslib.distance_field(ifs, 32, 2, dtype=torch.float64, gradient=mode))  # noqa: E731
    grads = {}
    for mode in ("exact", "paper"):
        ifs.points.grad = None
        loss(mode).backward()
        grads[mode] = ifs.points.grad.clone()
    fd = torch.zeros_like(grads["exact"])
    with torch.no_grad():
        for i in range(5):
            for j in range(2):
                h = 1e-6
                ifs.points[i, j] += h
                up = loss("exact").item()
                ifs.points[i, j] -= 2 * h
                down = loss("exact").item()
                ifs.points[i, j] += h
                fd[i, j] = (up - down) / (2 * h)
    torch.testing.assert_close(grads["exact"], fd, rtol=1e-4, atol=1e-6)
    assert (grads["paper"] - fd).abs().max() > 0.1 * fd.abs().max()


def test_bad_arguments_are_clear_errors():
    ifs = ifslib.patterns.koch()
    with pytest.raises(ValueError, match="unknown method 'approx'"):
        ifslib.distance_field(ifs, 8, method="approx")
    with pytest.raises(ValueError, match="size must be an integer >= 1"):
        ifslib.distance_field(ifs, 0)
    with pytest.raises(ValueError, match="depth must be an integer >= 0"):
        ifslib.distance_field(ifs, 8, depth=-1)
    with pytest.raises(ValueError, match="unknown device"):
        ifslib.distance_field(ifs, 8, device="tpu")
    with pytest.raises(ValueError, match="dtype must be"):
        ifslib.distance_field(ifs, 8, dtype=torch.int32)


def test_memory_budget_is_checked_before_allocating():
    ifs = ifslib.patterns.grid(3)
    with pytest.raises(ValueError, match=r"depth 12 with 9 rules makes 282,429,536,481 leaf maps.*over the memory budget"):
        ifslib.distance_field(ifs, 64, depth=12)
    with pytest.raises(ValueError, match="over the memory budget of 0.00 GiB"):
        ifslib.distance_field(ifslib.patterns.koch(), 64, depth=2, memory_budget=1000)


def test_nan_points_are_rejected():
    ifs = ifslib.patterns.koch()
    with torch.no_grad():
        ifs.points[2, 1] = float("nan")
    with pytest.raises(ValueError, match=r"control point\(s\) \[2\] are not finite"):
        ifslib.distance_field(ifs, 8)
