"""literature_ifs: random IFSs of the literature's classes (stem, spiral, overlap, many), each with its property,
contracting, fitted into the frame, neither dust nor a blob by the float64 chaos game, and reproducible."""
import math

import numpy as np
import pytest
import torch

import ifslib
from ifslib.errors import IFSError
from ifslib.core.geometry.patterns import sierpinski_triangle
from ifslib.core.geometry.random_fractals import random_ifs
from ifslib.core.geometry.rules import singular_values
from common_testing import benchmark_module

samplers = benchmark_module("samplers")
(OVERLAP_AREA, OVERLAP_SHARE, SPIRAL_SCALE, SPIRAL_TURN, STEM_THIN, Acceptance, copy_overlap, literature_ifs,
 occupancy) = (getattr(samplers, n) for n in ("OVERLAP_AREA", "OVERLAP_SHARE", "SPIRAL_SCALE", "SPIRAL_TURN",
                                              "STEM_THIN", "Acceptance", "copy_overlap", "literature_ifs", "occupancy"))

#: The drawn IFSs of the tests: (kind, maps, seed), the ends of each class's range of maps.
DRAWN = [("stem", 3, 0), ("stem", 6, 1), ("spiral", 2, 0), ("spiral", 4, 1), ("overlap", 2, 0), ("overlap", 5, 1),
         ("many", 6, 0), ("many", 10, 1)]

# drawing every class's IFSs (a module fixture) takes about 12 s: the slow tier
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def drawn():
    return {key: literature_ifs(*key) for key in DRAWN}


def maps_of(ifs):
    return ifs.to(torch.float64).maps().detach()


@pytest.mark.parametrize("key", DRAWN, ids=lambda k: f"{k[0]}{k[1]}_{k[2]}")
def test_every_map_contracts_and_the_count_is_asked(drawn, key):
    ifs = drawn[key]
    assert len(ifs.rules) == key[1] and ifs.name == f"{key[0]}{key[1]}_{key[2]}"
    assert float(singular_values(maps_of(ifs))[1].max()) < 1


@pytest.mark.parametrize("key", DRAWN, ids=lambda k: f"{k[0]}{k[1]}_{k[2]}")
def test_the_attractor_fills_the_frame_and_is_neither_dust_nor_a_blob(drawn, key):
    # the float64 chaos game, independent of the sampled leaves the sampler judged by
    points = ifslib.chaos_game(drawn[key], 400_000, seed=3)
    lo, hi = points.min(0), points.max(0)
    # the box the sampler fits is certified within 1/200 to 1/25 of the attractor's radius (the coarser for
    # many overlapping maps), and the chaos game's box is inside the true one
    assert np.abs((lo + hi) / 2).max() < 0.015          # centred
    assert (hi - lo).max() == pytest.approx(0.8, abs=0.03)
    share = ifslib.render(drawn[key], 128, method="chaos", points=400_000).numpy().__ge__(0.5).mean()
    assert 0.015 < share < 0.65


def test_a_stem_is_one_or_two_maps_of_rank_one_or_nearly(drawn):
    for key in [("stem", 3, 0), ("stem", 6, 1)]:
        smallest = singular_values(maps_of(drawn[key]))[0]
        thin = int((smallest < STEM_THIN + 1e-6).sum())
        assert thin in (1, 2), f"{key}: smallest singular values {smallest.tolist()}"
        assert float(smallest[smallest >= STEM_THIN + 1e-6].min()) > 0.1   # the copies hung on it have width


def test_a_spiral_has_one_dominant_turning_similarity(drawn):
    for key in [("spiral", 2, 0), ("spiral", 4, 1)]:
        m = maps_of(drawn[key])
        smallest, largest = singular_values(m)
        similar = (largest - smallest).abs() < 1e-5
        dominant = [i for i in range(len(m)) if similar[i] and SPIRAL_SCALE[0] <= largest[i] <= SPIRAL_SCALE[1]]
        assert len(dominant) == 1, f"{key}: singular values {smallest.tolist()} {largest.tolist()}"
        a = m[dominant[0], :2, :2]
        assert float(torch.linalg.det(a)) > 0                       # a rotation, not a reflection
        turn = abs(math.degrees(math.atan2(float(a[1, 0]), float(a[0, 0]))))
        assert SPIRAL_TURN[0] - 1e-3 <= turn <= SPIRAL_TURN[1] + 1e-3
        others = [i for i in range(len(m)) if i != dominant[0]]
        assert float(largest[others].max()) < 0.5


def test_overlapping_copies_overlap(drawn):
    for key in [("overlap", 2, 0), ("overlap", 5, 1)]:
        m = maps_of(drawn[key])
        area = float(torch.linalg.det(m[:, :2, :2]).abs().sum())
        assert OVERLAP_AREA[0] - 1e-3 <= area <= OVERLAP_AREA[1] + 1e-3
        assert copy_overlap(m) >= OVERLAP_SHARE


def test_copy_overlap_against_known_cases():
    # the Sierpinski triangle's copies meet only at three points; two equal maps overlap everywhere
    triangle = maps_of(sierpinski_triangle())
    assert copy_overlap(triangle) < 0.05
    twice = torch.cat([triangle, triangle[:1]])
    assert copy_overlap(twice) > copy_overlap(triangle) + 0.2


def test_many_is_the_anderson_farrell_sampler(drawn):
    for key in [("many", 6, 0), ("many", 10, 1)]:
        m = maps_of(drawn[key])
        tries = [maps_of(random_ifs(key[1], key[2] * samplers.ACCEPT.attempts + a)) for a in range(4)]
        assert any(torch.allclose(m, t, atol=1e-6) for t in tries)


def test_the_same_seed_gives_the_same_ifs(drawn):
    again = literature_ifs("spiral", 4, 1)
    assert torch.equal(again.points, drawn[("spiral", 4, 1)].points)
    assert not torch.equal(literature_ifs("spiral", 4, 2).points, again.points)


def test_occupancy_uses_the_render_grid():
    grid = occupancy(np.array([[-0.49, 0.49]]), 8)       # top left corner of the frame
    assert grid[0, 0] and grid[0, 1] and grid[1, 0] and not grid[1, 1] and grid.sum() == 3


@pytest.mark.parametrize("args, kwargs, words", [
    (("fern", 4, 0), {}, "stem, spiral, overlap, many"),
    (("stem", 2, 0), {}, ">= 3"),
    (("spiral", 5, 0), {}, "from 2 to 4"),
    (("many", 11, 0), {}, "from 6 to 10"),
    (("overlap", True, 0), {}, "integer"),
    (("stem", 3, -1), {}, "seed"),
    (("stem", 3, 0), {"extent": 1.5}, "at most 1"),
    (("stem", 3, 0), {"extent": 0}, "extent"),
    (("spiral", 2, 0), {"accept": Acceptance(share=(0.99, 1.0), points=5000, attempts=2)}, "passed in 2 draws"),
])
def test_bad_arguments_are_refused(args, kwargs, words):
    with pytest.raises(IFSError) as info:
        literature_ifs(*args, **kwargs)
    assert words in str(info.value)

