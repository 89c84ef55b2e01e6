"""The frame every run of a fit shares: its pyramid is built once, and only when a strategy climbs it."""
import pytest

import ifslib
from ifslib.core.fitting.frame import Frame


def test_the_pyramid_is_built_once_when_first_asked_for():
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 128)
    frame = Frame(target, 5, 0, progress=False, settings=ifslib.strategies.Pyramid(coarsest=32))
    assert "levels" not in vars(frame)  # a plain run never pays for the resizing
    assert frame.sizes == [32, 128] and frame.levels[128] is target
    assert frame.levels is frame.levels


def test_the_frame_takes_its_options_by_name():
    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 32)
    with pytest.raises(TypeError):
        Frame(target, 5, 0, False)
