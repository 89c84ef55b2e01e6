"""`ifslib.core.geometry.primitives`: segment, box and disk distances under shear and reflection against formulas in
the plane, the disk's bound, and float32 accuracy for nearly flat maps."""
import math

import pytest
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import sdf_dense
from ifslib.core.raster.nearest import pixel_centres
from ifslib.core.geometry.primitives import Primitive
from ifslib.errors import IFSError

from common_testing import point_segment as _point_segment, polygon_sdf as _polygon_sdf, random_affine as _random_affine


@pytest.mark.parametrize("seed", range(6))
def test_segment_and_box_distances_are_exact_under_shear_and_reflection(seed):
    """One affine word: the field equals the distance to the image segment / parallelogram, computed in the plane."""
    a, t = _random_affine(seed, reflect=seed % 2 == 1)
    maps = torch.cat([a, t[:, None]], 1)[None] * 0.9
    lo, hi = torch.tensor([-0.3, -0.2], dtype=torch.float64), torch.tensor([0.25, 0.3], dtype=torch.float64)
    base = ifslib.patterns.affine(maps, depth=1, primitive="box")
    pts = torch.cat([base.points.detach(), torch.stack([lo, hi])])
    prims = [{"kind": "segment", "points": [7, 8]}, {"kind": "box", "points": [7, 8]}]
    ifs = ifslib.IFS(pts, base.rules, prims, depth=1, dtype=torch.float64)
    A, T = maps[0, :, :2], maps[0, :, 2]
    image = lambda p: A @ p + T  # noqa: E731
    corners = [image(torch.stack(c)) for c in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1]))]
    if torch.det(A) < 0:  # _polygon_sdf wants counter-clockwise corners
        corners = corners[::-1]
    x = (torch.rand(60, 2, generator=torch.Generator().manual_seed(seed), dtype=torch.float64) - 0.5) * 1.2
    inner = lo + (hi - lo) * torch.tensor([[0.5, 0.5], [0.1, 0.8], [0.9, 0.3]], dtype=torch.float64)
    x = torch.cat([x, (inner @ A.T) + T])  # some queries inside the parallelogram
    got = sdf_dense(expand(ifs, 1), x[:, 0], x[:, 1]).detach()  # (63, 2): the segment, the box
    for i, p in enumerate(x):
        want = torch.stack([_point_segment(p, image(lo), image(hi)), _polygon_sdf(p, corners)])
        torch.testing.assert_close(got[i], want)
    assert (got[:, 1] < 0).any() and (got[:, 1] > 0).any()


def test_the_disk_under_shear_is_bounded_below_and_exact_on_its_ellipse():
    """A disk's image is an ellipse: the field is a 1-Lipschitz lower bound of its distance, zero on it."""
    a = torch.tensor([[0.6, 0.3], [0.0, 0.2]], dtype=torch.float64)
    maps = torch.cat([a, torch.zeros(2, 1, dtype=torch.float64)], 1)[None]
    base = ifslib.patterns.affine(maps, depth=1)
    pts = torch.cat([base.points.detach(), torch.tensor([[0.0, 0.0]], dtype=torch.float64)])
    ifs = ifslib.IFS(pts, base.rules, [{"kind": "disk", "points": [7], "radius": 0.4}], depth=1, dtype=torch.float64)
    theta = torch.linspace(0, 2 * math.pi, 20001, dtype=torch.float64)
    ellipse = (a @ (0.4 * torch.stack([theta.cos(), theta.sin()])) ).T  # the ellipse, densely
    x, y = pixel_centres(40, dtype=torch.float64)
    field = sdf_dense(expand(ifs, 1), x, y)[:, 0].detach()
    true = torch.cdist(torch.stack([x, y], 1), ellipse).min(1).values  # unsigned, to within the sampling
    inside = field < 0
    assert inside.any() and (~inside).any()
    assert (field[~inside] <= true[~inside] + 1e-4).all()             # a lower bound outside
    assert (field[inside].abs() <= true[inside] + 1e-4).all()          # and inside
    lo, hi = torch.linalg.svdvals(a).tolist()[::-1]
    assert (field[~inside] >= true[~inside] * lo / hi - 1e-4).all()    # within sigma_min / sigma_max of it
    # 1-Lipschitz along the rows and columns of the grid
    grid = field.view(40, 40)
    assert grid.diff(dim=0).abs().max() <= 1 / 40 + 1e-12 and grid.diff(dim=1).abs().max() <= 1 / 40 + 1e-12


def test_nearly_flat_maps_keep_float32_distances_accurate():
    """A deep word of nearly flat maps has an inverse in the millions; segments and boxes are measured from
    the forward map, so float32 stays within rounding of float64 (pulling back and pushing forward did not)."""
    maps = [[[0.45, 0.0, -0.2], [0.0, 0.002, -0.2]], [[0.45, 0.0, 0.2], [0.0, 0.003, 0.1]],
            [[0.3, 0.1, 0.0], [0.0, 0.0015, 0.25]]]
    for primitive in ("box", "segment"):
        wide = ifslib.patterns.affine(maps, depth=3, primitive=primitive, dtype=torch.float64)
        narrow = wide.to(torch.float32)
        assert expand(narrow).inverse.abs().max() > 1e6
        fast32 = ifslib.distance_field(narrow, 40).double()
        torch.testing.assert_close(fast32, ifslib.distance_field(wide, 40), rtol=0, atol=1e-5)
        torch.testing.assert_close(fast32, ifslib.distance_field(narrow, 40, method="brute").double(), rtol=0, atol=1e-6)


def test_each_kind_carries_its_points_radius_and_packing():
    # what the code branches on comes from the table, one module a kind (ifslib/core/geometry/shapes/)
    from ifslib.core.geometry.primitives import PARAM_WIDTH, PRIMITIVE_KINDS, primitive_params
    from ifslib.core.geometry.shapes import SHAPES

    assert set(PRIMITIVE_KINDS) == set(SHAPES) >= {"segment", "box", "disk"}
    points = torch.tensor([[0.1, -0.2], [0.3, 0.4], [-0.4, 0.2], [0.0, 0.3]])
    for kind, shape in SHAPES.items():
        prim = Primitive(kind, tuple(range(shape.points)), radius=0.05)
        assert primitive_params(points, [prim]).shape == (1, PARAM_WIDTH)
        with pytest.raises(IFSError, match=f"needs {shape.points} point"):
            Primitive(kind, tuple(range(shape.points + 1)), radius=0.05)
    assert [k for k, s in SHAPES.items() if s.radius == "required"] == ["disk"]
    with pytest.raises(IFSError, match="radius > 0"):
        Primitive("disk", (0,))


def _slope_cases():
    """Each kind with a slope, its packed parameters, and points on its edge, its centre and inside it."""
    from ifslib.core.geometry.primitives import PARAM_WIDTH

    def row(*v):
        return torch.tensor(list(v) + [0.0] * (PARAM_WIDTH - len(v)), dtype=torch.float64)

    return {
        "bare segment": ("segment", row(-0.2, -0.1, 0.3, 0.2, 0.0), [[0.05, 0.05], [-0.2, -0.1], [0.3, 0.2]]),
        "thick segment": ("segment", row(-0.2, -0.1, 0.3, 0.2, 0.05), [[0.05, 0.05], [0.0, 0.05]]),
        "box": ("box", row(-0.3, -0.1, 0.2, 0.3, 0.0), [[-0.05, 0.1], [-0.3, 0.0], [0.2, 0.3], [0.0, 0.3],
                                                       [-0.1, 0.2], [-0.25, 0.25]]),
        "disk": ("disk", row(0.1, -0.2, 0.15), [[0.1, -0.2], [0.25, -0.2], [0.12, -0.15]]),
    }


@pytest.mark.parametrize("case", sorted(_slope_cases()))
def test_each_slope_is_its_distance_and_a_subgradient(case):
    # the nearest-leaf search bounds a leaf by its tangent plane (ifslib.core.raster.nearest): the slope's
    # value must be `local`'s bit for bit, its gradient autograd's off the kinks, and the plane must stay
    # below the distance everywhere, at the kinks too (the edge, the centre, a corner, the medial axis)
    from ifslib.core.geometry.shapes import SHAPES

    kind, params, special = _slope_cases()[case]
    shape = SHAPES[kind]
    g = torch.Generator().manual_seed(3)
    q = torch.cat([torch.tensor(special, dtype=torch.float64), torch.rand(400, 2, generator=g, dtype=torch.float64) - 0.5])
    qx, qy = q[:, 0].clone().requires_grad_(), q[:, 1].clone().requires_grad_()
    d = shape.local(qx, qy, params.unbind(-1))
    value, gx, gy, reach = shape.slope(qx.detach(), qy.detach(), params.unbind(-1))
    assert torch.equal(value, d.detach())
    wx, wy = torch.autograd.grad(d.sum(), [qx, qy])
    smooth = slice(len(special), None)  # random points: off every kink
    torch.testing.assert_close(gx[smooth], wx[smooth], rtol=0, atol=1e-12)
    torch.testing.assert_close(gy[smooth], wy[smooth], rtol=0, atol=1e-12)
    assert (torch.hypot(gx, gy) <= 1 + 1e-12).all()
    # the reach is the length of the vector the gradient is the direction of: where it is finite, the
    # distance from the nearest point of the segment, the centre or the box (offset by the radius)
    finite = torch.isfinite(reach)
    assert finite.any() and (reach[finite] >= 0).all()
    assert (reach[finite] - (value[finite] + (params[2] if kind == "disk" else params[4] if kind == "segment" else 0))
            ).abs().max() < 1e-12
    # the tangent plane at every point stays below the distance at every other point (convexity)
    plane = value[:, None] + gx[:, None] * (q[None, :, 0] - q[:, None, 0]) + gy[:, None] * (q[None, :, 1] - q[:, None, 1])
    assert (plane <= value[None, :] + 1e-12).all()
