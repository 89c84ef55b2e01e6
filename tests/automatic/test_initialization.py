"""`ifslib.automatic.initialization.initialize`: a pattern placed on the target (the paper's start), its
arguments checked before any work; the automatic start itself is tested in test_plan and test_auto."""
import numpy as np
import pytest

import ifslib
from ifslib.core.targets.placement import place


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=2), 32)


def test_a_pattern_is_placed_and_jittered_with_its_seed(koch_target):
    pattern = ifslib.patterns.koch(depth=2)
    plain = ifslib.initialize(pattern, koch_target)
    assert isinstance(plain, ifslib.IFS) and plain is not pattern
    assert np.array_equal(plain.points.detach().numpy(), place(pattern, koch_target).points.detach().numpy())
    a, b = (ifslib.initialize(pattern, koch_target, jitter=0.05, seed=7).points.detach().numpy() for _ in range(2))
    moved = a - plain.points.detach().numpy()
    assert np.array_equal(a, b) and 0 < np.abs(moved).max() <= 0.05


@pytest.mark.parametrize("call, message", [
    (lambda t: ifslib.initialize("koch", t), "initialize takes an IFS or 'auto'"),
    (lambda t: ifslib.initialize(ifslib.patterns.koch(), t, maps=3), "maps and depth are for initialize"),
    (lambda t: ifslib.initialize(ifslib.patterns.koch(), t, depth=2), "maps and depth are for initialize"),
    (lambda t: ifslib.initialize("auto", t, jitter=1.5), "jitter must be a number from 0 to 1"),
    (lambda t: ifslib.initialize(ifslib.patterns.koch(), t, seed=-1), "seed"),
])
def test_bad_arguments_are_refused_before_any_work(koch_target, call, message):
    with pytest.raises(ifslib.IFSError, match=message):
        call(koch_target)
