"""benchmarks/batch.py's batched fitting: every batched piece equals its one-IFS counterpart, and fit_many equals fit
per seed."""
import pytest
import torch

import ifslib
from ifslib.core.geometry.leaves import expand
from ifslib.core.raster.leaf_distance import leaf_table, sdf_pairs, sdf_table
from ifslib.core.raster.nearest import nearest_leaf, pixel_centres

from common_testing import benchmark_module
from conftest import PATTERNS, perturbed

batching = benchmark_module("batch")
distance_fields, expand_batch, fit_many = batching.distance_fields, batching.expand_batch, batching.fit_many

SIZE = 32


def _batch(name, n=3, dtype=torch.float64):
    base = PATTERNS[name]()
    return base, [perturbed(base, 0.01, seed=s, dtype=dtype) for s in range(n)]


def test_batched_maps_leaves_and_search_equal_each_item(pattern_name):
    base, items = _batch(pattern_name)
    points = torch.stack([i.points.detach() for i in items])
    assert torch.equal(ifslib.rule_maps(points, base.rules), torch.stack([i.maps().detach() for i in items]))
    batch = expand_batch(base, points, 2)
    assert batch.n_items == 3 and len(batch) == 3 * items[0].n_leaves(2)
    found = nearest_leaf(batch, SIZE)
    per_item = len(batch) // 3
    for b, item in enumerate(items):
        alone = nearest_leaf(expand(item, 2), SIZE)
        pix = slice(b * SIZE * SIZE, (b + 1) * SIZE * SIZE)
        assert torch.equal(found.leaf[pix] - b * per_item, alone.leaf)
        assert torch.equal(found.distance[pix], alone.distance)


def test_batched_fields_and_gradients_equal_each_item():
    base, items = _batch("mixed")
    points = torch.stack([i.points.detach() for i in items]).requires_grad_(True)
    fields = distance_fields(base, points, SIZE, 2)
    fields.square().sum().backward()
    for b, item in enumerate(items):
        alone = ifslib.distance_field(item, SIZE, 2)
        alone.square().sum().backward()
        assert torch.allclose(fields[b], alone, atol=1e-12)
        assert torch.allclose(points.grad[b], item.points.grad, atol=1e-10)


def test_leaf_table_gives_the_same_distances_bit_for_bit():
    leaves = expand(perturbed(ifslib.patterns.koch(depth=3), 0.02, dtype=torch.float32), 3).detach()
    x, y = pixel_centres(SIZE, "cpu", torch.float32)
    leaf = torch.randint(0, len(leaves), (x.numel(),), generator=torch.Generator().manual_seed(0))
    assert torch.equal(sdf_table(leaf_table(leaves), "segment", x, y, leaf), sdf_pairs(leaves, x, y, leaf))
    assert leaf_table(expand(PATTERNS["mixed"](), 1)) is None  # several kinds: sdf_pairs is used


def test_batched_losses_equal_each_item():
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 16)
    fields = torch.rand(3, 16, 16, dtype=torch.float64) - 0.1
    for kind in ifslib.LOSSES:
        got = ifslib.loss(fields, target, kind)
        assert got.shape == (3,)
        assert torch.allclose(got, torch.stack([ifslib.loss(f, target, kind) for f in fields]))
    custom = ifslib.loss(fields, target, lambda d, t: d.mean())
    assert torch.allclose(custom, fields.mean(dim=(1, 2)))


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=2), SIZE)


def _paper_start(seed):
    return ifslib.patterns.koch_paper(seed, depth=2)


@pytest.mark.parametrize("gradient", ["exact", "paper"])
def test_fit_many_equals_fit_for_every_seed(koch_target, gradient):
    kw = dict(steps=25, lr=0.003, loss="multiscale_distance", options=ifslib.RunOptions(gradient=gradient), progress=False)
    many = fit_many(_paper_start, koch_target, seeds=[0, 1, 2], **kw)
    for seed, got in zip([0, 1, 2], many):
        want = ifslib.fit(_paper_start(seed), koch_target, seed=seed, **kw, strategy="plain")
        assert torch.equal(got.final.points, want.final.points)
        assert torch.equal(got.best.points, want.best.points)
        assert got.history.loss == want.history.loss
        assert (got.best_loss, got.best_step) == (want.best_loss, want.best_step)


def test_fit_many_rolls_back_each_seed_as_fit_does(koch_target):
    # a learning rate this large makes rules non-contractive: each seed rolls back on its own
    kw = dict(steps=30, lr=0.2, loss="multiscale_distance", progress=False)
    many = fit_many(_paper_start, koch_target, seeds=[0, 1, 2, 3], **kw)
    assert any(r.history.rollbacks for r in many)
    for seed, got in enumerate(many):
        want = ifslib.fit(_paper_start(seed), koch_target, seed=seed, **kw, strategy="plain")
        assert [(r["step"], r["lr"]) for r in got.history.rollbacks] == \
            [(r["step"], r["lr"]) for r in want.history.rollbacks]
        assert torch.equal(got.final.points, want.final.points)
        assert got.history.cost == want.history.cost == 30


def test_fit_many_keeps_fixed_points_and_takes_a_list_or_a_jittered_start(koch_target):
    start = ifslib.initialize(ifslib.patterns.koch(depth=2), koch_target)
    start.fixed = (0, 4)
    many = fit_many(start, koch_target, seeds=[5, 6], steps=5, jitter=0.02, progress=False)
    assert not torch.equal(many[0].final.points, many[1].final.points)
    for got in many:
        assert torch.equal(got.final.points[[0, 4]], start.points.detach()[[0, 4]])
    # the jitter is drawn from the seed: the same seed gives the same start
    again = fit_many(start, koch_target, seeds=[6], steps=0, jitter=0.02, progress=False)[0]
    assert again.history.cost == 0
    assert not torch.equal(again.final.points, start.points.detach())
    assert torch.equal(again.final.points, fit_many(start, koch_target, seeds=[6], steps=0, jitter=0.02,
                                                    progress=False)[0].final.points)
    listed = fit_many([_paper_start(3), _paper_start(4)], koch_target, seeds=[3, 4], steps=3, progress=False)
    assert torch.equal(listed[1].final.points, fit_many(_paper_start, koch_target, seeds=[4], steps=3,
                                                        progress=False)[0].final.points)


def test_fit_many_bad_inputs_are_clear_errors(koch_target):
    with pytest.raises(ifslib.IFSError, match="at least one seed"):
        fit_many(_paper_start, koch_target, seeds=[])
    with pytest.raises(ifslib.IFSError, match="one per seed"):
        fit_many([_paper_start(0)], koch_target, seeds=[0, 1])
    with pytest.raises(ifslib.IFSError, match="not the same pattern"):
        fit_many([_paper_start(0), ifslib.patterns.sierpinski_carpet()], koch_target, seeds=[0, 1])
    with pytest.raises(ifslib.IFSError, match="lr must be"):
        fit_many(_paper_start, koch_target, seeds=[0], lr=float("nan"))
    with pytest.raises(ifslib.IFSError, match="unknown gradient mode"):
        fit_many(_paper_start, koch_target, seeds=[0], gradient="cut")


def test_fit_and_fit_many_on_the_device_follow_the_cpu_path(koch_target, device):
    # on CPU this is the same computation twice; with --device cuda it checks the GPU path
    kw = dict(steps=10, lr=0.003, loss="multiscale_distance", progress=False)
    on_cpu = ifslib.fit(_paper_start(0), koch_target, **kw, strategy="plain", options=ifslib.RunOptions(device="cpu"))
    here = ifslib.fit(_paper_start(0), koch_target, **kw, strategy="plain", options=ifslib.RunOptions(device=device))
    batched = fit_many(_paper_start, koch_target, seeds=[0, 1], device=device, **kw)[0]
    for got in (here, batched):
        torch.testing.assert_close(got.final.points.detach().cpu(), on_cpu.final.points.detach(), rtol=0, atol=1e-4)
