"""`ifslib.core.fitting.options`: every setting checked once, where the options are built."""
from __future__ import annotations

import pytest

import ifslib
from ifslib.core.fitting.options import RunOptions, StrategyOptions, split_settings
from ifslib.core.raster.distance import METHODS
from ifslib.core.scoring.losses import DEFAULT_LOSS, LOSSES
from ifslib.studies.sweep import Cell

# (field, the known names the refusal lists)
NAMED = [("loss", LOSSES), ("method", METHODS), ("gradient", ("exact", "paper")), ("device", ("auto", "cpu", "cuda"))]


@pytest.mark.parametrize("name, known", NAMED, ids=[n for n, _ in NAMED])
def test_an_unknown_name_is_refused_when_the_options_are_built(name, known):
    with pytest.raises(ifslib.IFSError, match=f"unknown {name}") as refused:
        RunOptions(**{name: "typo"})
    assert all(k in str(refused.value) for k in known), str(refused.value)
    with pytest.raises(ifslib.IFSError, match=f"unknown {name}"):
        RunOptions().replace(**{name: "typo"})  # a copy is checked as well


@pytest.mark.parametrize("name, known", NAMED, ids=[n for n, _ in NAMED])
def test_every_known_name_builds(name, known):
    for value in known:
        assert getattr(RunOptions(**{name: value}), name) == value


def test_a_loss_may_be_a_function():
    def mine(distance, target):
        return distance.mean()

    assert RunOptions(loss=mine).loss is mine


def test_the_library_the_command_line_and_the_sweep_share_one_default_loss():
    from ifslib.cli import _fit_options, build_parser

    args = build_parser().parse_args(["fit", "koch", "-o", "x.json"])
    assert RunOptions().loss == _fit_options(args).loss == Cell().loss == DEFAULT_LOSS


def test_named_settings_go_to_their_object_and_unknown_ones_are_refused():
    run, strategy = split_settings({"loss": "pixel", "n_starts": 3}, None, None)
    assert (run.loss, strategy.n_starts) == ("pixel", 3)
    assert run.replace(loss=DEFAULT_LOSS) == RunOptions() and strategy == StrategyOptions(n_starts=3)
    with pytest.raises(ifslib.IFSError, match="unknown setting"):
        split_settings({"los": "pixel"}, None, None)


@pytest.mark.parametrize("lr", [0, -1, float("nan"), float("inf"), 1.5, True, "0.1"])
def test_a_bad_lr_is_refused_where_the_options_are_built(lr):
    with pytest.raises(ifslib.IFSError, match="lr must be a finite number > 0 and at most 1"):
        RunOptions(lr=lr)
    with pytest.raises(ifslib.IFSError, match="lr must be a finite number > 0 and at most 1"):
        split_settings({"lr": lr}, None, None)  # by name, through the same check


def test_a_stage_scales_the_lr_without_the_cap_and_a_fit_cannot_set_it_by_name():
    options = RunOptions(lr=0.5)
    staged = options.replace(stage_lr=options.lr * 256 / 64)  # a coarse stage's step: 2 plane units at 64²
    assert (options.step_lr, staged.step_lr, staged.lr) == (0.5, 2.0, 0.5)
    with pytest.raises(ifslib.IFSError, match="stage_lr"):
        RunOptions(stage_lr=float("nan"))
    with pytest.raises(ifslib.IFSError, match="unknown setting"):
        split_settings({"stage_lr": 0.1}, None, None)
