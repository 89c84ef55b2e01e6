"""The fractal search's settings (`SearchConfig`): bad values refused, `dataclasses.replace` round trips, and a
changed setting changes what the search does."""
from dataclasses import FrozenInstanceError, fields, replace

import numpy as np
import pytest

import ifslib
from ifslib.automatic import fractal
from ifslib.automatic.fractal import DEFAULT, SearchConfig
from ifslib.errors import IFSError
from ifslib.core.targets.target import resize_target, target_from_mask

BAD = [("keep", 0), ("keep", 2.0), ("keep", True), ("search_size", 1), ("again", -1), ("turns", "12"),
       ("min_scale", 0.0), ("min_scale", 0.95), ("max_scale", 1.0), ("inside", 1.5), ("swap_below", 0.0),
       ("swap_below", 1.2), ("map_cost", -0.1), ("give_up_px", float("inf")), ("chamfer_cost", float("nan")),
       ("overlap", "half"), ("fractal_maps", ()), ("fractal_maps", (3, 2)), ("fractal_maps", [2, 3]),
       ("fractal_maps", (2, 17)), ("fractal_maps", (0, 2)), ("fractal_maps", ("2",)), ("collage_points", (600,)),
       ("collage_points", (600, 0)), ("collage_points", [600, 2000])]


@pytest.mark.parametrize("name, value", BAD, ids=[f"{n}={v!r}" for n, v in BAD])
def test_bad_settings_are_refused_with_a_message_naming_the_field(name, value):
    with pytest.raises(IFSError, match=name):
        replace(DEFAULT, **{name: value})


def test_replace_round_trips_and_the_config_is_frozen():
    changed = replace(DEFAULT, again=0, map_cost=0.1, collage_points=(300, 1000))
    assert changed != DEFAULT and (changed.again, changed.map_cost, changed.collage_points) == (0, 0.1, (300, 1000))
    back = replace(changed, again=DEFAULT.again, map_cost=DEFAULT.map_cost, collage_points=DEFAULT.collage_points)
    assert back == DEFAULT == SearchConfig() and hash(back) == hash(DEFAULT)
    assert all(getattr(back, f.name) == getattr(DEFAULT, f.name) for f in fields(SearchConfig))
    with pytest.raises(FrozenInstanceError):
        DEFAULT.again = 0
    # the edge values each check allows
    replace(DEFAULT, inside=0.0, swap_below=1.0, again=0, reorient=0, fractal_maps=(16,), min_scale=0.5, max_scale=0.6)


def test_the_numbers_of_maps_follow_the_config_and_a_config_must_be_one():
    small = replace(DEFAULT, fractal_maps=(2, 3), max_maps=3)
    assert fractal.check_maps(None, config=small) == (2, 3)
    assert fractal.check_maps(3, config=small) == (3,)
    with pytest.raises(IFSError, match="at most 3 maps"):
        fractal.check_maps(4, config=small)
    with pytest.raises(IFSError, match="max_maps"):
        replace(small, max_maps=2)  # fractal_maps would exceed it
    truth = ifslib.random_fractals.random_ifs(2, 4)
    target = target_from_mask(ifslib.render(truth, 32, method="chaos", points=100_000, seed=4).numpy() >= 0.5)
    with pytest.raises(IFSError, match="SearchConfig"):
        fractal.search(target, maps=2, progress=False, config={"again": 0})


@pytest.mark.slow
def test_again_and_the_bar_change_what_the_search_does_on_a_small_fractal():
    """With a bar no attractor reaches (IoU 1), ``again=1`` runs the search from seeds 0 and 1 and keeps the one
    whose chosen maps score least; ``again=0`` runs it once. The map cost set reaches the scores and the rule."""
    truth = ifslib.random_fractals.random_ifs(2, 4)
    mask = ifslib.render(truth, 256, method="chaos", points=1_000_000, seed=4).numpy() >= 0.5
    target = resize_target(target_from_mask(mask), 32)
    strict = replace(DEFAULT, swap_below=1.0, map_cost=0.25, region_rounds=0, grow_rounds=0, swap_rounds=0,
                     search_steps=60, refine_steps=60, judge_points=100_000)  # fewer steps: the same choices
    once = fractal.search(target, maps=2, progress=False, config=replace(strict, again=0))
    other = fractal.search(target, maps=2, seed=1, progress=False, config=replace(strict, again=0))
    twice = fractal.search(target, maps=2, progress=False, config=strict)
    assert once.chosen["iou"] < 1.0 and once.chosen["reoriented"]
    assert "ran from seeds" not in once.rule and "plus 0.25 a map" in once.rule
    assert once.choice.score == 1 - once.choice.iou + 0.25 * 2  # full precision; the file's row rounds it
    assert once.chosen["score"] == round(once.choice.score, 4) and once.chosen["iou"] == round(once.choice.iou, 4)
    assert f"seeds 0-1, whose chosen maps scored {once.choice.score:.3f}, {other.choice.score:.3f}" in twice.rule
    best = min((once, other), key=lambda r: (r.choice.score, len(r.maps)))
    assert np.array_equal(twice.maps, best.maps) and _untimed(twice.table) == _untimed(best.table)


def _untimed(table):
    return [{k: v for k, v in row.items() if k != "seconds"} for row in table]
