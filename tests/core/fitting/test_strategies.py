"""Strategies on small sizes: each runs, counts its steps, and returns a result at least as good as its start."""
import importlib
import math

import numpy as np

import pytest

import ifslib
from ifslib.core.fitting import pyramid, strategies
from ifslib.core.fitting.frame import Frame
from ifslib.core.fitting.strategies import DEFAULT_STRATEGY, STRATEGIES

SIZE, STEPS = 32, 12


@pytest.fixture(scope="module")
def target():
    return ifslib.load_target(ifslib.patterns.koch(depth=2), SIZE)


@pytest.mark.parametrize("strategy", STRATEGIES)
def test_strategy_runs_and_counts_its_cost(strategy, target):
    if strategy == "splat":
        importlib.import_module("ifslib.splatting")  # an extension's strategy is in the table once its folder is imported
    # the auto strategy fits an automatic start (its candidates are the curve's 2, 3 and 4 maps)
    start = ifslib.discover(target, depth=2) if strategy == "auto" else ifslib.patterns.koch_paper(1, depth=2)
    result = ifslib.fit(start, target, steps=STEPS, loss="multiscale_distance", progress=False, strategy=strategy)
    cost = result.history.cost
    assert (result.history.strategy or "plain") == strategy
    if strategy == "multistart":
        assert STEPS < cost <= 3 * STEPS
    elif strategy == "pyramid":  # up to 8 starts, two stages each at this size (the drawing's, the attractor's)
        assert 0 < cost <= 16 * STEPS and 2 * result.history.starts_tried == len(result.history.stages)
        assert all(s.depth == "attractor" for s in result.history.stages[1::2])
    elif strategy == "auto":  # a probe of each candidate, the chosen one's stage (one size here), its attractor's
        assert 0 < cost <= 5 * STEPS and len(result.history.stages) == 2
    elif strategy == "restart":
        assert 0 < cost <= 3 * STEPS
    else:
        assert cost == STEPS
    weight = ifslib.strategies.Uncross().weight if strategy == "uncross" else 0.0  # its loss includes the crossing barrier
    depth = "attractor" if strategy in ("pyramid", "auto") else None  # those end on the attractor
    start_loss = ifslib.fit(start, target, steps=1, loss="multiscale_distance", progress=False, strategy="plain",
                            options=ifslib.RunOptions(crossing_weight=weight), depth=depth).best_loss
    assert result.best_loss <= start_loss


def test_coarse_to_fine_ends_at_full_depth(target):
    result = ifslib.fit(ifslib.patterns.koch_paper(1, depth=2), target, steps=6, loss="distance",
                        progress=False, strategy="coarse_to_fine")
    assert result.best.depth == 2


def test_restart_stops_early_on_success(target):
    start = ifslib.initialize(ifslib.patterns.koch(depth=2), target)
    result = ifslib.fit(start, target, steps=30, loss="multiscale_distance", progress=False, strategy="restart")
    assert result.history.cost == 10  # the first window already lies within a pixel


def test_unknown_strategy_and_checkpoint_are_refused(target, tmp_path):
    with pytest.raises(ifslib.IFSError, match="known strategies"):
        ifslib.fit(ifslib.patterns.koch(depth=2), target, steps=2, strategy="magic")
    with pytest.raises(ifslib.IFSError, match="plain"):
        ifslib.fit(ifslib.patterns.koch(depth=2), target, steps=2, strategy="multistart", checkpoint=tmp_path / "c.json")


def test_uncross_needs_a_curve(target):
    with pytest.raises(ifslib.IFSError, match="needs a curve"):
        ifslib.fit(ifslib.patterns.sierpinski_carpet(depth=1), target, steps=2, progress=False, strategy="uncross")
    with pytest.raises(ifslib.IFSError, match="crossing_weight must be"):
        ifslib.RunOptions(crossing_weight=-1)


def test_default_is_pyramid_and_a_single_run_when_checkpointing(target, tmp_path):
    start = ifslib.patterns.koch_paper(1, depth=2)
    result = ifslib.fit(start, target, steps=STEPS, loss="multiscale_distance", progress=False)
    assert result.history.strategy == DEFAULT_STRATEGY == "pyramid"
    assert 0 < result.history.cost <= 8 * STEPS
    single = ifslib.fit(start, target, steps=4, progress=False, checkpoint=tmp_path / "c.json")
    assert single.history.cost == 4 and single.history.strategy is None


def test_attractor_stage_falls_back_to_sampled_leaves_when_the_cut_outgrows_the_budget(monkeypatch):
    """The stage starts with the certified cut when it is small enough (`attractor_method`), but maps that grow during
    the stage can make the cut outgrow the leaf budget (benchmark fractal 3 did, and the command failed): the stage
    then runs again with sampled leaves, and its record says so."""
    from ifslib.core.geometry import attractor

    ifs = ifslib.patterns.koch(depth=3)
    target = ifslib.load_target(ifslib.render(ifs, 64).detach().numpy(), 64)
    assert pyramid.attractor_method(ifs, 64, ifslib.strategies.Pyramid().max_leaves) == "fast"
    monkeypatch.setattr(attractor, "DEFAULT_MAX_LEAVES", 16)  # the stage's own cut: far over this budget at once
    frame = Frame(target, 2, 0, progress=False)
    result, record = pyramid.attractor_stage(frame, ifs, ifslib.RunOptions(lr=1e-3), "test")
    assert record.method == "sampled" and "outgrew the leaf budget" in record.fallback
    assert math.isfinite(result.best_loss)


def test_a_fit_calls_no_discovery(target, monkeypatch):
    """The pyramid's best-fit-line starts are placed by `ifslib.core.targets.placement`: every discovery entry point
    switched off, a fit of a pattern (a plan's too, handed in whole) still runs."""
    from ifslib.automatic import auto, fractal, plan
    from ifslib.core.targets import placement

    plan_of_koch = ifslib.discover(target, depth=2)

    def off(*args, **kwargs):
        raise AssertionError("a fit called discovery")

    for module, name in [(placement, "initialize"), (plan, "discover"), (plan, "plan_for"),
                         (auto, "candidates"), (plan, "fractal_start"), (fractal, "search"), (ifslib, "initialize")]:
        monkeypatch.setattr(module, name, off)
    start = ifslib.patterns.koch_paper(1, depth=2)
    result = ifslib.fit(start, target, steps=4, strategy=ifslib.strategies.Pyramid(n_starts=2, success=0.0), progress=False)
    assert result.history.starts_tried == 2  # the second start is the one placed on the best-fit line
    assert ifslib.fit(plan_of_koch, target, steps=4, progress=False).history.strategy == "auto"


def test_the_second_pyramid_start_is_the_pattern_on_the_best_fit_line(target):
    from ifslib.core.targets.placement import best_fit_line, placed_points

    start = ifslib.patterns.koch_paper(1, depth=2)
    line = strategies.starts(start, target, 2, 0.05, np.random.default_rng(0))[1]
    centre, direction, lo, hi = best_fit_line(target)
    on_line = centre + np.linspace(lo, hi, start.n_points)[:, None] * direction
    assert np.allclose(line.points.detach().numpy(), on_line, atol=1e-6)
    assert np.allclose(placed_points(start, target), on_line)
