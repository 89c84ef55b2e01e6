"""Barnsley's collage distance (`ifslib.core.scoring.collage`): lowest for the true maps, its gradient against
central differences."""
import torch

import ifslib
from ifslib.core.scoring.collage import collage_distance


def test_collage_distance_is_lowest_for_the_true_maps_and_its_gradient_is_right():
    quarters = [[[0.5, 0.0, x], [0.0, 0.5, y]] for x in (-0.15, 0.15) for y in (-0.15, 0.15)]
    truth = ifslib.patterns.affine(quarters, depth=2, extent=0.6, dtype=torch.float64)  # copies tile the square
    target = ifslib.load_target(truth, 40)  # the square the four maps tile, drawn at depth 2
    exact = collage_distance(truth, target).item()
    pts = truth.points.detach().clone()
    pts[4:7] += torch.tensor([0.06, -0.04], dtype=torch.float64)  # one copy slid off its quarter
    # and every copy a little off the pixel grid, so that no two nearest copies tie (ties are kinks)
    pts[4:] += (torch.rand(pts[4:].shape, generator=torch.Generator().manual_seed(3), dtype=torch.float64) - 0.5) * 0.01
    moved = truth.clone(pts)
    assert exact < 0.5 * collage_distance(moved, target).item()
    # the gradient: central differences of the same sample, with the nearest copies held (a smooth piece)
    work = moved.clone()
    value = collage_distance(work, target, n=300)
    value.backward()
    for i, j in ((4, 0), (6, 1), (9, 0), (12, 1)):
        h = 1e-6
        up, down = work.clone(), work.clone()
        with torch.no_grad():
            up.points[i, j] += h
            down.points[i, j] -= h
        fd = (collage_distance(up, target, n=300) - collage_distance(down, target, n=300)).item() / (2 * h)
        assert abs(fd - work.points.grad[i, j].item()) <= 1e-4 * max(1.0, abs(fd))
