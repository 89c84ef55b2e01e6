"""`ifslib.core.scoring.metrics`: IoU, F1 and Chamfer on small masks; the point error up to a similarity."""
import numpy as np
import pytest
import torch

import ifslib


def test_metrics():
    a = np.zeros((10, 10), bool)
    a[2, 2:8] = True
    b = np.zeros((10, 10), bool)
    b[3, 2:8] = True
    assert ifslib.iou(a, a) == 1 and ifslib.iou(a, b) == 0 and ifslib.f1(a, a) == 1
    assert ifslib.chamfer(a, b) == pytest.approx(1.0) and ifslib.chamfer(a, a) == 0
    koch = ifslib.patterns.koch()
    moved = koch.clone(koch.points.detach() * 0.5 + torch.tensor([0.1, -0.2]))  # a similarity of it
    assert ifslib.point_error(moved, koch) < 1e-6
    mirrored = koch.clone(koch.points.detach() * torch.tensor([1.0, -1.0]))
    assert ifslib.point_error(mirrored, koch) < 1e-6
    bent = koch.clone(koch.points.detach() + torch.tensor([[0, 0], [0, 0], [0, 0.05], [0, 0], [0, 0]]))
    assert ifslib.point_error(bent, koch) > 0.02
