"""`ifslib.automatic.config`: the automatic path's tuned numbers, one frozen config checked where it is built."""
from __future__ import annotations

import dataclasses

import pytest

import ifslib
from ifslib.automatic import auto, plan
from ifslib.automatic.config import AUTO, AutoFitConfig, FigureConfig, StartConfig
from ifslib.automatic import fit_plan as automatic


def test_the_modules_read_the_one_config():
    assert auto.FIGURE is AUTO.figure is plan.FIGURE and auto.START is AUTO.start and automatic.FIT is AUTO.fit
    assert AUTO.search is ifslib.automatic.fractal.DEFAULT
    assert AUTO.ambiguous_search == dataclasses.replace(AUTO.search, again=AUTO.figure.ambiguous_again)


def test_every_field_has_a_line_on_what_it_trades():
    import inspect

    from ifslib.automatic import config

    source = inspect.getsource(config)
    for section in (FigureConfig, StartConfig, AutoFitConfig):
        for f in dataclasses.fields(section):
            line = next(i for i, text in enumerate(source.splitlines()) if text.strip().startswith(f"{f.name}:"))
            assert source.splitlines()[line - 1].strip().startswith("#"), f"{section.__name__}.{f.name} has no comment"


@pytest.mark.parametrize("section, changes, message", [
    (FigureConfig, {"porous_share": 1.5}, "porous_share is a share"),
    (FigureConfig, {"curve_width": float("nan")}, "curve_width must hold finite numbers"),
    (FigureConfig, {"thin_radius": 0}, "thin_radius"),
    (FigureConfig, {"ambiguous_again": -1}, "ambiguous_again"),
    (StartConfig, {"singular_range": (0.5, 0.2)}, "singular_range"),
    (StartConfig, {"shape_choices": ((8, 0),)}, "shape_choices"),
    (AutoFitConfig, {"polish_loss": "typo"}, "unknown loss"),
    (AutoFitConfig, {"probe_steps": 0}, "probe_steps"),
    (AutoFitConfig, {"splat_below": 1.5}, "splat_below is a share"),
    (AutoFitConfig, {"splat_lr": 0.0}, "splat_lr must be a learning rate"),
    (AutoFitConfig, {"splat_steps": 0}, "splat_steps"),
])
def test_a_bad_number_is_refused_when_the_config_is_built(section, changes, message):
    with pytest.raises(ifslib.IFSError, match=message):
        section(**changes)
    assert FigureConfig(ambiguous_again=0).ambiguous_again == 0  # a count that may be 0
