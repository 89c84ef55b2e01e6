"""`ifslib.core.fitting.options`: every setting checked once, where the options are built."""
from __future__ import annotations

import dataclasses

import pytest

import ifslib
from ifslib.core.fitting.options import (Anneal, CoarseToFine, Multistart, Plain, Pyramid, Restart, RunOptions,
                                         Uncross, with_settings)
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


def test_run_settings_by_name_and_unknown_ones_are_refused():
    assert with_settings(None, {"loss": "pixel"}) == RunOptions(loss="pixel")
    assert with_settings(RunOptions(tol=0.01), {"loss": "pixel"}) == RunOptions(tol=0.01, loss="pixel")
    with pytest.raises(ifslib.IFSError, match="unknown setting"):
        with_settings(None, {"los": "pixel"})
    with pytest.raises(ifslib.IFSError, match="unknown setting.*n_starts"):
        with_settings(None, {"n_starts": 3})  # a strategy's: in its own options object


STRATEGY_OPTIONS = [Pyramid, Multistart, Restart, Uncross, Plain, CoarseToFine, Anneal]


def test_each_strategy_has_its_own_small_options_and_fit_takes_them_whole():
    assert all(len(dataclasses.fields(cls)) <= 11 for cls in STRATEGY_OPTIONS)
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 24)
    start = ifslib.patterns.koch_paper(1, depth=2)
    by_name = ifslib.fit(start, target, steps=6, strategy="multistart", progress=False)
    by_object = ifslib.fit(start, target, steps=6, strategy=Multistart(), progress=False)
    assert by_name.best_loss == by_object.best_loss and by_object.history.strategy == "multistart"
    fewer = ifslib.fit(start, target, steps=6, strategy=Pyramid(n_starts=1, success=0.0), progress=False)
    assert fewer.history.starts_tried == 1
    with pytest.raises(ifslib.IFSError, match="strategy must be a name .* or a strategy's options"):
        ifslib.fit(start, target, steps=6, strategy=RunOptions(), progress=False)


@pytest.mark.parametrize("cls, field, value, message", [
    (Pyramid, "n_starts", 0, "n_starts"), (Pyramid, "pyramid_factor", 1, "pyramid_factor"),
    (Pyramid, "stage_tol", 0.0, "stage_tol must be a finite number > 0"),
    (Pyramid, "end_on_attractor", 1, "end_on_attractor must be True or False"),
    (Multistart, "probe", 1.0, "probe must be a share"), (Multistart, "keep", 0, "keep"),
    (Restart, "budget", 0.0, "budget must be a finite number > 0"),
    (Restart, "jitter", -0.1, "jitter must be a finite number >= 0"),
    (Uncross, "weight", float("nan"), "weight must be a finite number > 0"),
])
def test_a_strategy_option_out_of_range_is_refused_where_it_is_built(cls, field, value, message):
    with pytest.raises(ifslib.IFSError, match=message):
        cls(**{field: value})


@pytest.mark.parametrize("lr", [0, -1, float("nan"), float("inf"), 1.5, True, "0.1"])
def test_a_bad_lr_is_refused_where_the_options_are_built(lr):
    with pytest.raises(ifslib.IFSError, match="lr must be a finite number > 0 and at most 1"):
        RunOptions(lr=lr)
    with pytest.raises(ifslib.IFSError, match="lr must be a finite number > 0 and at most 1"):
        ifslib.fit(ifslib.patterns.koch(), ifslib.load_target(ifslib.patterns.koch(depth=1), 16), lr=lr)  # by name


def test_a_stage_scales_the_lr_without_the_cap_and_a_fit_cannot_set_it_by_name():
    options = RunOptions(lr=0.5)
    staged = options.replace(stage_lr=options.lr * 256 / 64)  # a coarse stage's step: 2 plane units at 64²
    assert (options.step_lr, staged.step_lr, staged.lr) == (0.5, 2.0, 0.5)
    with pytest.raises(ifslib.IFSError, match="stage_lr"):
        RunOptions(stage_lr=float("nan"))
    with pytest.raises(ifslib.IFSError, match="unknown setting"):
        with_settings(None, {"stage_lr": 0.1})
