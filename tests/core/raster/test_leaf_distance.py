"""`ifslib.core.raster.leaf_distance`: the slope lookup gives `sdf_table`'s distances bit for bit and autograd's
gradients, for similarity and sheared words of each kind; tables of mixed kinds have none."""
import pytest
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import has_slope, leaf_table, sdf_pairs, sdf_table, sdf_table_slope

from conftest import PATTERNS, perturbed, sheared, sheared_disks


def _disks(depth=2, dtype=torch.float64):
    """The Koch rules drawing a disk: a similarity pattern of the disk kind alone."""
    koch = ifslib.patterns.koch(depth=depth)
    points = torch.cat([koch.points.detach().double(), torch.tensor([[0.05, 0.1]], dtype=torch.float64)])
    return ifslib.IFS(points, koch.rules, [{"kind": "disk", "points": [5], "radius": 0.08}], depth=depth,
                      fixed=koch.fixed, dtype=dtype)


#: one kind a pattern, under similarity words (the table's 12 rows) or sheared ones (18 rows: the forward maps)
SLOPED = {"koch": lambda: ifslib.patterns.koch(), "carpet": lambda: ifslib.patterns.sierpinski_carpet(),
          "disks": _disks, "sheared boxes": lambda: sheared("box"), "sheared segments": lambda: sheared("segment"),
          "sheared disks": sheared_disks}


@pytest.mark.parametrize("name", sorted(SLOPED))
@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_the_slope_lookup_is_the_table_s_distance_and_autograd_s_gradient(name, dtype):
    ifs = perturbed(SLOPED[name](), seed=5, dtype=dtype)
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
    # two roundings of one direction: they may differ by what the search allows for (ROUNDING_ULPS / reach)
    from ifslib.core.raster.nearest import ROUNDING_ULPS

    allowed = 1e-5 + 2 * ROUNDING_ULPS * torch.finfo(dtype).eps / reach
    assert (torch.hypot(gx - wx, gy - wy) <= allowed).all()
    assert (torch.hypot(gx - wx, gy - wy) <= 1e-5).float().mean() > 0.99


@pytest.mark.parametrize("name", ["affine_mixed", "mixed"])
def test_mixed_kinds_have_no_slope_lookup(name):
    # a table of mixed kinds is None: the search falls back to the Lipschitz bound for them
    leaves = expand(PATTERNS[name](), 2)
    assert leaf_table(leaves) is None and not has_slope(leaf_table(leaves), leaves.kinds[0])
