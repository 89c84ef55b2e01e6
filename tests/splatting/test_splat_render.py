"""The splat renderer against the exact measure (cylinders), finite differences, and itself at two thread counts."""
import numpy as np
import pytest
import torch
from scipy import ndimage

from ifslib.errors import IFSError
from ifslib.measures.measure import cylinder_measure
from ifslib.core.geometry import patterns
from ifslib.splatting import SplatOptions, coverage, splat_measure



def similarity(angle: float, scale: float, tx: float, ty: float) -> list:
    c, s = scale * np.cos(angle), scale * np.sin(angle)
    return [[c, -s, tx], [s, c, ty], [0, 0, 1]]


#: Three turned similarities of scale about 1/2 with unequal probabilities: no edge of the attractor lies along the
#: pixel grid (a Sierpinski triangle's do, where a splat and a histogram part most).
MAPS = torch.tensor([similarity(0.3, 0.5, -0.17, -0.21), similarity(-0.7, 0.45, 0.19, -0.13),
                     similarity(2.0, 0.48, 0.03, 0.22)], dtype=torch.float64)
P = torch.tensor([0.5, 0.3, 0.2], dtype=torch.float64)


def exact_splat(size: int, k: int, p=P) -> np.ndarray:
    """What a bilinear splat at ``k`` fine cells a pixel gives in expectation, summed into pixels: the cylinders'
    cell masses at the fine grid blurred by [1/8, 3/4, 1/8] (a point uniform in its cell), then summed."""
    ifs = patterns.affine(MAPS, dtype=torch.float64)
    ifs.probabilities = tuple(p.tolist())
    fine, _ = cylinder_measure(ifs, size * k)
    tap = np.array([1 / 8, 3 / 4, 1 / 8])
    fine = ndimage.convolve1d(ndimage.convolve1d(fine, tap, 0, mode="constant"), tap, 1, mode="constant")
    return fine.reshape(size, k, size, k).sum((1, 3))


def test_density_matches_cylinder_measure_within_sampling_noise():
    # the reference's own error (a point taken uniform in its fine cell) falls like 1 / supersample: at 8 it is
    # about 0.017 in L1, half the sampling noise of 131,072 points
    n = 2048 * 64
    image = splat_measure(MAPS, P, 32, SplatOptions(points=n, supersample=8)).numpy()
    exact = exact_splat(32, 8)
    lit = int((exact > 0).sum())
    noise = np.sqrt(2 * lit / (np.pi * n))  # L1 of a histogram of n independent draws over `lit` cells
    assert abs(image.sum() - 1) < 1e-9
    assert np.abs(image - exact).sum() < 2 * noise
    wrong = exact_splat(32, 8, torch.tensor([0.2, 0.3, 0.5], dtype=torch.float64))
    assert np.abs(image - wrong).sum() > 10 * noise  # the probabilities are seen


def weighted_sum(maps, p, seed=0, depth=30, size=24):
    weights = torch.linspace(0, 1, size * size, dtype=torch.float64).view(size, size).sin()
    return (splat_measure(maps, p, size, SplatOptions(points=2048 * 8, depth=depth, seed=seed)) * weights).sum()


def test_map_gradient_matches_finite_differences():
    maps = MAPS.clone().requires_grad_(True)
    weighted_sum(maps, P).backward()
    eps = 1e-6
    for i, r, c in [(0, 0, 0), (1, 0, 2), (2, 1, 0), (2, 1, 2), (0, 0, 1)]:
        plus, minus = MAPS.clone(), MAPS.clone()
        plus[i, r, c] += eps
        minus[i, r, c] -= eps
        fd = (float(weighted_sum(plus, P)) - float(weighted_sum(minus, P))) / (2 * eps)
        assert abs(float(maps.grad[i, r, c]) - fd) <= 1e-4 * max(1.0, abs(fd)), (i, r, c)


def test_probability_gradient_points_as_the_exact_measure_moves():
    size = 16
    weights = torch.linspace(0, 1, size * size, dtype=torch.float64).view(size, size).sin()
    logits = P.log().clone().requires_grad_(True)
    image = splat_measure(MAPS, logits.softmax(0), size, SplatOptions(points=2048 * 100, depth=12, supersample=2))
    (image * weights).sum().backward()
    fd = []
    for i in range(3):
        moved = []
        for sign in (1, -1):
            q = P.log().clone()
            q[i] += sign * 0.05
            moved.append(float((torch.as_tensor(exact_splat(size, 2, q.softmax(0))) * weights).sum()))
        fd.append((moved[0] - moved[1]) / 0.1)
    fd, grad = np.array(fd), logits.grad.numpy()
    assert grad @ fd / (np.linalg.norm(grad) * np.linalg.norm(fd)) > 0.95
    assert 0.7 < np.linalg.norm(grad) / np.linalg.norm(fd) < 1.3


def test_same_image_and_gradient_at_one_and_two_threads():
    before = torch.get_num_threads()
    out = []
    try:
        for threads in (1, 2):
            torch.set_num_threads(threads)
            maps = MAPS.float().requires_grad_(True)
            image = splat_measure(maps, P.float(), 32, SplatOptions(points=2048 * 16, seed=3))
            (image ** 2).sum().backward()
            out.append((image.detach(), maps.grad))
    finally:
        torch.set_num_threads(before)
    assert torch.equal(out[0][0], out[1][0]) and torch.equal(out[0][1], out[1][1])


def test_seed_changes_the_points_and_float32_follows_the_maps():
    a = splat_measure(MAPS.float(), P.float(), 32, SplatOptions(points=4096, seed=0))
    b = splat_measure(MAPS.float(), P.float(), 32, SplatOptions(points=4096, seed=1))
    assert a.dtype == torch.float32 and not torch.equal(a, b)


@pytest.mark.parametrize("maps, p, message", [
    (MAPS * torch.tensor([2.5, 2.5, 1.0])[:, None, None].expand(3, 3, 3).clone(), P, "not contractive"),
    (MAPS, torch.tensor([0.5, 0.5, 0.5], dtype=torch.float64), "sum to 1"),
    (MAPS, torch.tensor([0.5, 0.5], dtype=torch.float64), "shape"),
    (MAPS.new_full((3, 3, 3), float("nan")), P, "finite"),
    (MAPS[:, :2, :2], P, "shape"),
])
def test_bad_maps_and_probabilities_are_refused(maps, p, message):
    with pytest.raises(IFSError, match=message):
        splat_measure(maps, p, 16, SplatOptions(points=2048))


def test_bad_options_and_memory_are_refused(monkeypatch):
    with pytest.raises(IFSError, match="points"):
        SplatOptions(points=0)
    with pytest.raises(IFSError, match="supersample"):
        SplatOptions(supersample=0)
    with pytest.raises(IFSError, match="options"):
        splat_measure(MAPS, P, 16, options={"points": 10})
    monkeypatch.setattr("ifslib.core.geometry.leaves.DEFAULT_MEMORY_BUDGET", 1 << 20)
    with pytest.raises(IFSError, match="memory budget"):
        splat_measure(MAPS, P, 16, SplatOptions(points=1_000_000))


def test_coverage_reads_visited_pixels_as_figure():
    density = torch.tensor([0.0, 0.01, 1.0], requires_grad=True)
    cov = coverage(density, 0.01)
    assert cov[0] == 0 and abs(float(cov[1].detach()) - (1 - np.exp(-1))) < 1e-6 and cov[2] > 0.99
    cov.sum().backward()
    assert (density.grad[:2] > 0).all() and density.grad[2] >= 0  # a well covered pixel's pull vanishes
    with pytest.raises(IFSError):
        coverage(density, 0.0)
