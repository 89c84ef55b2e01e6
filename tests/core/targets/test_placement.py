"""`ifslib.core.targets.placement`: a curve on the best-fit line, evenly spaced; any other pattern on the bounding box."""
import numpy as np
import pytest

import ifslib

SIZE, DEPTH = 48, 2


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=DEPTH), SIZE)


def test_best_fit_line_initialization(koch_target):
    centre, direction, lo, hi = ifslib.best_fit_line(koch_target)
    assert abs(direction[1]) < 0.2  # the Koch curve lies along x
    start = ifslib.initialize(ifslib.patterns.koch(), koch_target)
    pts = start.points.detach().numpy()
    assert np.allclose(np.diff(pts[:, 0]), (hi - lo) / 4 * direction[0], atol=1e-6)  # evenly spaced on the line
    carpet = ifslib.initialize(ifslib.patterns.sierpinski_carpet(), ifslib.load_target(np.pad(np.ones((10, 10)), 3), 16))
    p = carpet.points.detach().numpy()
    assert p.min() == pytest.approx(-0.5 + 3.5 / 16) and p.max() == pytest.approx(-0.5 + 12.5 / 16)


def test_a_pattern_is_placed_and_jittered_with_its_seed(koch_target):
    pattern = ifslib.patterns.koch(depth=2)
    plain = ifslib.initialize(pattern, koch_target)
    assert isinstance(plain, ifslib.IFS) and plain is not pattern
    a, b = (ifslib.initialize(pattern, koch_target, jitter=0.05, seed=7).points.detach().numpy() for _ in range(2))
    moved = a - plain.points.detach().numpy()
    assert np.array_equal(a, b) and 0 < np.abs(moved).max() <= 0.05


@pytest.mark.parametrize("call, message", [
    (lambda t: ifslib.initialize("koch", t), "initialize takes an IFS, got 'koch': patterns by name"),
    (lambda t: ifslib.initialize("auto", t), r"a start read from the image is ifslib.discover\(target\)"),
    (lambda t: ifslib.initialize(np.zeros((3, 2)), t), "initialize takes an IFS"),
    (lambda t: ifslib.initialize(ifslib.patterns.koch(), t, jitter=1.5), "jitter must be a number from 0 to 1"),
    (lambda t: ifslib.initialize(ifslib.patterns.koch(), t, seed=-1), "seed"),
])
def test_bad_arguments_are_refused_before_any_work(koch_target, call, message):
    with pytest.raises(ifslib.IFSError, match=message):
        call(koch_target)
