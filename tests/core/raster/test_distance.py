"""`ifslib.core.raster.distance`: fast == brute on every pattern, exact gradients, float32 and float64, bad inputs."""
import pytest
import torch

import ifslib

from conftest import PATTERNS, mixed, perturbed


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


def test_nan_points_are_rejected():
    ifs = ifslib.patterns.koch()
    with torch.no_grad():
        ifs.points[2, 1] = float("nan")
    with pytest.raises(ValueError, match=r"control point\(s\) \[2\] are not finite"):
        ifslib.distance_field(ifs, 8)
