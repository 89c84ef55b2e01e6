"""Early stopping, the target's resolution pyramid, and the default ``pyramid`` strategy, at small sizes."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib.core.fitting.options import RunOptions
from ifslib.core.fitting.descent import converged
from ifslib.core.fitting.run import run
from ifslib.core.targets.target import pyramid_sizes, resize_target

KOCH = ifslib.patterns.koch(depth=2)


@pytest.fixture(scope="module")
def target():
    return ifslib.load_target(KOCH, 32)


def test_converged_reads_the_best_loss_over_a_window():
    assert not converged([5, 4, 3], tol=0.0, patience=3)               # too few steps to judge
    assert converged([5, 4, 4, 4, 4], tol=0.0, patience=3)             # no new best in the last 3
    assert not converged([5, 4, 4, 4, 3.9], tol=0.0, patience=3)
    assert converged([5, 4, 4, 4, 3.9], tol=0.05, patience=3)          # 2.5% better: below a 5% tolerance
    assert not converged([5, 4, 4, 4, 3.9], tol=0.01, patience=3)


def test_pyramid_sizes():
    assert pyramid_sizes(256, 64) == [64, 128, 256]
    assert pyramid_sizes(256, 64, 4) == [64, 256]
    assert pyramid_sizes(512, 64, 4) == [64, 256, 512]
    assert pyramid_sizes(1024, 64, 4) == [64, 256, 1024]
    assert pyramid_sizes(100, 64) == [100] and pyramid_sizes(128, 64, 4) == [64, 128]
    with pytest.raises(ifslib.IFSError, match="factor"):
        pyramid_sizes(256, 64, 3)


def test_resize_target_keeps_a_thin_curve_connected_and_a_shape_its_area():
    curve = ifslib.load_target(ifslib.patterns.koch(depth=3), 256)
    small = resize_target(curve, 64)
    assert small.size == 64 and resize_target(curve, 256) is curve
    # every pixel of the coarse curve lies within one coarse pixel of the fine curve, and back
    assert ifslib.chamfer(small.mask, resize_target(curve, 64).mask) == 0
    fine_on_coarse = np.zeros((64, 64), bool)
    rows, cols = np.nonzero(curve.mask)
    fine_on_coarse[rows // 4, cols // 4] = True
    assert ifslib.chamfer(small.mask, fine_on_coarse) <= 1.0
    disk = np.hypot(*np.meshgrid(np.arange(256) - 127.5, np.arange(256) - 127.5)) < 80
    shape = ifslib.load_target(disk.astype(float), 256)
    assert abs(resize_target(shape, 64).mask.mean() - disk.mean()) < 0.01


@pytest.mark.slow
def test_early_stop_is_the_same_run_cut_short(target):
    start = ifslib.initialize(KOCH, target, jitter=0.03, seed=1)
    short = run(start, target, steps=200, progress=False,
                options=RunOptions(lr=0.01, loss="multiscale_distance", tol=1e-3, patience=10))
    assert short.history.stopped == "converged" and short.history.cost < 200
    n = short.history.cost
    full = run(start, target, steps=n, progress=False, options=RunOptions(lr=0.01, loss="multiscale_distance"))
    assert full.history.stopped == "steps"
    assert short.history.loss == full.history.loss
    assert torch.equal(short.final.points, full.final.points)


@pytest.mark.slow
def test_early_stop_ends_where_the_full_run_ends(target):
    # where both converge, stopping early costs no accuracy: the same points as 400 more steps
    start = ifslib.initialize(KOCH, target, jitter=0.03, seed=2)
    kwargs = dict(lr=0.01, loss="multiscale_distance", progress=False, strategy="plain")
    early = ifslib.fit(start, target, steps=300, options=ifslib.RunOptions(tol=1e-3, patience=10), **kwargs)
    full = ifslib.fit(start, target, steps=300, **kwargs)
    assert early.history.cost < 150
    assert ifslib.point_error(early.best, full.best) < 0.01
    assert ifslib.evaluate(early.best, target)["chamfer"] <= 1.0


@pytest.mark.slow
def test_pyramid_recovers_a_posed_curve_from_the_best_fit_line():
    posed = KOCH.clone(KOCH.points.detach() @ torch.tensor([[0.0, -0.7], [0.7, 0.0]]))
    target = ifslib.load_target(posed, 128)
    start = ifslib.initialize(KOCH, target)
    result = ifslib.fit(start, target, steps=300, loss="multiscale_distance", progress=False)
    history = result.history
    assert history.strategy == "pyramid" and history.recovered
    assert [s.size for s in history.stages][:2] == [64, 128]
    assert all(s.stopped == "converged" for s in history.stages)
    assert history.chamfer <= 1.0 and ifslib.point_error(result.best, posed) < 0.02
    assert result.best.meta["history"]["strategy"] == "pyramid"  # what a saved fit records


def test_pyramid_tries_the_next_start_when_one_fails(target):
    # success=0 px cannot be met, so every start is tried and the best is kept
    result = ifslib.fit(KOCH, target, steps=10, loss="multiscale_distance", progress=False,
                        strategy=ifslib.strategies.Pyramid(n_starts=3, success=0.0))
    assert result.history.starts_tried == 3 and not result.history.recovered
    assert {s.start for s in result.history.stages} == {0, 1, 2}
    assert result.history.cost == sum(s.steps for s in result.history.stages)


def test_bad_stop_arguments(target):
    with pytest.raises(ifslib.IFSError, match="tol"):
        ifslib.RunOptions(tol=-1)
    with pytest.raises(ifslib.IFSError, match="patience"):
        ifslib.RunOptions(tol=0.1, patience=0)
    with pytest.raises(ifslib.IFSError, match="Target"):
        ifslib.fit(KOCH, np.zeros((8, 8)), steps=2, progress=False)


def test_the_attractor_stage_samples_leaves_past_its_leaf_budget():
    from ifslib.core.fitting.frame import Frame
    from ifslib.core.fitting.options import RunOptions
    from ifslib.core.fitting.pyramid import attractor_method, attractor_stage
    from ifslib.core.raster.distance import attractor_leaves_for

    fern = ifslib.patterns.fern()
    leaves = len(attractor_leaves_for(fern, 64))
    assert attractor_method(fern, 64, leaves) == "fast" and attractor_method(fern, 64, leaves - 1) == "sampled"
    target = ifslib.load_target(ifslib.render(fern, 64, depth="attractor").detach().numpy(), 64)
    frame = Frame(target, 4, 0, progress=False)
    for budget, method in ((leaves, "fast"), (leaves - 1, "sampled")):
        _, stage = attractor_stage(frame, fern, RunOptions(loss="pixel"), "fern", max_leaves=budget)
        assert stage.method == method and stage.depth == "attractor" and stage.steps == 4
