"""`ifslib.core.raster.leaf_distance`: the table lookups give `sdf_pairs`'s distances bit for bit, and the slope
lookup autograd's gradients, for the tables that carry them."""
import pytest
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import has_slope, leaf_table, sdf_pairs, sdf_table, sdf_table_slope

from conftest import PATTERNS, perturbed


def _disks(depth=2, dtype=torch.float64):
    """The Koch rules drawing a disk: a similarity pattern of the disk kind alone."""
    koch = ifslib.patterns.koch(depth=depth)
    points = torch.cat([koch.points.detach().double(), torch.tensor([[0.05, 0.1]], dtype=torch.float64)])
    return ifslib.IFS(points, koch.rules, [{"kind": "disk", "points": [5], "radius": 0.08}], depth=depth,
                      fixed=koch.fixed, dtype=dtype)


SIMILAR = {"koch": lambda: ifslib.patterns.koch(), "carpet": lambda: ifslib.patterns.sierpinski_carpet(),
           "disks": _disks}


@pytest.mark.parametrize("name", sorted(SIMILAR))
@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_the_slope_lookup_is_the_table_s_distance_and_autograd_s_gradient(name, dtype):
    ifs = perturbed(SIMILAR[name](), seed=5, dtype=dtype)
    leaves = expand(ifs, 2)
    table = leaf_table(leaves)
    assert has_slope(table, leaves.kinds[0])
    g = torch.Generator().manual_seed(1)
    n = 3000
    x = (torch.rand(n, generator=g, dtype=torch.float64) - 0.5).to(dtype)
    y = (torch.rand(n, generator=g, dtype=torch.float64) - 0.5).to(dtype)
    leaf = torch.randint(len(leaves), (n,), generator=g)
    d, gx, gy, reach = sdf_table_slope(table, leaves.kinds[0], x, y, leaf)
    assert (reach > 0).all()
    assert torch.equal(d, sdf_table(table, leaves.kinds[0], x, y, leaf))
    xr, yr = x.clone().requires_grad_(), y.clone().requires_grad_()
    wx, wy = torch.autograd.grad(sdf_pairs(leaves.detach(), xr, yr, leaf).sum(), [xr, yr])
    tol = 1e-4 if dtype == torch.float32 else 1e-10
    torch.testing.assert_close(gx, wx, rtol=0, atol=tol)
    torch.testing.assert_close(gy, wy, rtol=0, atol=tol)


@pytest.mark.parametrize("name", ["affine", "affine_mixed", "mixed"])
def test_affine_words_and_mixed_kinds_have_no_slope_lookup(name):
    # a sheared word's distance is measured in the plane and a table of mixed kinds is None: the search
    # falls back to the Lipschitz bound for them
    leaves = expand(PATTERNS[name](), 2)
    assert not has_slope(leaf_table(leaves), leaves.kinds[0])
