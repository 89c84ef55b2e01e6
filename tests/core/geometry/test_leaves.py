"""`ifslib.core.geometry.leaves`: the leaves obey the SDF law of a similarity, and the memory estimate is checked before
anything is allocated."""
import math

import pytest
import torch
from common_testing import point_segment as _point_segment, polygon_sdf as _polygon_sdf

import ifslib
from ifslib.core.geometry.leaves import Leaves, invert_similarities
from ifslib.core.raster.leaf_distance import sdf_dense
from ifslib.core.geometry.primitives import primitive_params
from ifslib.core.raster.distance import Budget


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


def test_memory_budget_is_checked_before_allocating():
    ifs = ifslib.patterns.grid(3)
    with pytest.raises(ValueError, match=r"depth 12 with 9 rules makes 282,429,536,481 leaf maps.*over the memory budget"):
        ifslib.distance_field(ifs, 64, depth=12)
    with pytest.raises(ValueError, match="over the memory budget of 0.00 GiB"):
        ifslib.distance_field(ifslib.patterns.koch(), 64, depth=2, budget=Budget(memory=1000))
