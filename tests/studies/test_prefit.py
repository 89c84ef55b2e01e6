"""`ifslib.studies.prefit`: Adam on the collage distance lowers it and moves only the free points."""
import torch

import ifslib
from ifslib.core.scoring.collage import collage_distance
from ifslib.studies.prefit import collage_prefit


def test_the_prefit_lowers_the_collage_distance():
    quarters = [[[0.5, 0.0, x], [0.0, 0.5, y]] for x in (-0.15, 0.15) for y in (-0.15, 0.15)]
    truth = ifslib.patterns.affine(quarters, depth=2, extent=0.6, dtype=torch.float64)
    target = ifslib.load_target(truth, 40)
    pts = truth.points.detach().clone()
    pts[4:7] += torch.tensor([0.06, -0.04], dtype=torch.float64)  # one copy slid off its quarter
    moved = truth.clone(pts)
    fitted, history = collage_prefit(moved, target, steps=60, lr=0.005)
    assert min(history) < 0.5 * history[0] and torch.equal(fitted.points[:4], moved.points[:4])
    assert collage_distance(fitted, target).item() < collage_distance(moved, target).item()
