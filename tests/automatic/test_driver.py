"""`ifslib.automatic.fractal.driver`: the search's numbers of maps, bad input, and running again from the next seed."""
from dataclasses import replace

import numpy as np
import pytest
import torch

import ifslib
from ifslib.errors import IFSError
from ifslib.automatic import fractal
from ifslib.automatic.fractal import candidates, driver
from common_testing import fractal_target


def test_fractal_search_refuses_bad_numbers_of_maps_and_figures_with_no_copy(monkeypatch):
    _, target = fractal_target(size=32)
    for bad in (0, fractal.DEFAULT.max_maps + 1, 2.5):
        with pytest.raises(IFSError, match="maps"):
            fractal.search(target, maps=bad, progress=False)
    # a figure none of whose copies lies inside it (the candidates stood in for: the counts are exact, so which
    # figures have none is a matter of the grid, and a two-pixel speck has some; see test_determinism.py)
    monkeypatch.setattr(candidates, "copy_candidates", lambda mask, grid, **_: np.zeros((0, 4), np.int64))
    with pytest.raises(IFSError, match="no copy of the figure fits inside it"):
        fractal.search(target, maps=2, progress=False)


def test_search_compares_the_numbers_of_maps_given_and_sampled_leaves_refuse_a_map_near_scale_one():
    assert fractal.check_maps(None) == fractal.DEFAULT.fractal_maps
    assert fractal.check_maps([3, 2, 3]) == (2, 3)
    with pytest.raises(IFSError, match="at least one"):
        fractal.check_maps([])
    from ifslib.core.geometry.sampled import MAX_WORD_LENGTH, sample_attractor

    slow = torch.eye(3, dtype=torch.float64).repeat(2, 1, 1)
    slow[0, :2, :2] *= 0.99999
    slow[1, :2, :2] *= 0.5
    slow[1, :2, 2] = 0.2
    with pytest.raises(IFSError, match=f"more than {MAX_WORD_LENGTH}"):
        sample_attractor(slow, 1e-3, 64)


@pytest.mark.slow
def test_search_runs_again_from_the_next_seed_only_while_no_attractor_fits(monkeypatch):
    """`search` wraps one search (`_search`): run again from the next seed when no attractor reaches `swap_below`,
    and the search whose chosen maps score least kept (the searches themselves are stood in for)."""
    _, target = fractal_target(size=32)
    ious = {0: 0.6, 1: 0.7, 5: fractal.DEFAULT.swap_below}
    calls = []

    copies = set()

    def one(context, ks, progress, title):
        seed, config = context.seed, context.config
        calls.append(seed)
        copies.add(id(context.copies))  # the candidate copies do not depend on the seed: found once, read again
        row = fractal.Row(maps=2, cover=1.0, collage_px=0.0, iou=ious[seed], score=1 - ious[seed] + config.map_cost * 2,
                          reoriented=seed != 7)
        return fractal.SearchResult(np.full((2, 2, 3), seed / 10), (row,), f"rule {seed}")

    monkeypatch.setattr(driver, "_search", one)
    found = fractal.search(target, maps=2, seed=0, progress=False)
    assert calls == [0, 1] and found.maps[0, 0, 0] == 0.1 and len(copies) == 1
    assert found.rule.startswith("rule 1") and "seeds 0-1" in found.rule and "0.480, 0.380" in found.rule
    calls.clear()
    once = replace(fractal.DEFAULT, again=0)
    assert fractal.search(target, maps=2, seed=0, progress=False, config=once).rule == "rule 0" and calls == [0]
    calls.clear()
    found = fractal.search(target, maps=2, seed=5, progress=False)  # an attractor that fits: one search
    assert calls == [5] and found.rule == "rule 5"
    calls.clear()
    ious[7] = 0.3
    found = fractal.search(target, maps=2, seed=7, progress=False)  # gave up before reorienting: not a fractal
    assert calls == [7] and found.rule == "rule 7"
