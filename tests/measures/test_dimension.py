"""Dimension: Moran's equation against closed forms, box counting against the similarity dimension, bad input."""
import math

import numpy as np
import pytest

import ifslib
from ifslib.measures.dimension import (box_counting_image, box_counting_points, box_sizes, count_pixels,
                                      fit_box_dimension, ifs_scales, ifs_similarity_dimension, similarity_dimension)


@pytest.mark.parametrize("scales, expect", [
    ([0.5] * 3, math.log(3) / math.log(2)),
    ([1 / 3] * 4, math.log(4) / math.log(3)),
    ([1 / 3] * 8, math.log(8) / math.log(3)),
    ([0.5], 0.0),
])
def test_moran_with_equal_scales_is_log_m_over_log_one_over_r(scales, expect):
    assert similarity_dimension(scales) == pytest.approx(expect, abs=1e-10)


def test_moran_with_unequal_scales_solves_the_equation():
    r = [0.5, 0.25, 0.25, 0.1]
    d = similarity_dimension(r)
    assert sum(x ** d for x in r) == pytest.approx(1, abs=1e-10)
    # two scales 1/2 and 1/4: x = 2^-D solves x + x^2 = 1, so x is the golden ratio's inverse
    assert similarity_dimension([0.5, 0.25]) == pytest.approx(math.log((1 + 5 ** 0.5) / 2) / math.log(2), abs=1e-10)


@pytest.mark.parametrize("name, expect", [("triangle", math.log(3) / math.log(2)), ("koch", math.log(4) / math.log(3)),
                                          ("carpet", math.log(8) / math.log(3))])
def test_the_patterns_similarity_dimensions(name, expect):
    ifs = ifslib.patterns.by_name(name)
    assert ifs_scales(ifs)[1]  # all similarities
    assert ifs_similarity_dimension(ifs) == pytest.approx(expect, abs=1e-5)


def test_the_fern_is_not_a_similarity():
    assert not ifs_scales(ifslib.patterns.fern())[1]


def test_the_fit_recovers_a_known_power_law():
    sizes = box_sizes(64, 4, 1)
    fit = fit_box_dimension(sizes, np.round(3.0 * (1 / sizes) ** 1.5))
    assert fit.dimension == pytest.approx(1.5, abs=0.01) and fit.stderr < 0.01


def test_box_counts_by_hand():
    """A full 8 x 8 image: 4 boxes of 4 px, 16 of 2 px, 64 of 1 px; a single pixel: one box at every size."""
    np.testing.assert_array_equal(count_pixels(np.ones((8, 8)), [4, 2, 1]), [4, 16, 64])
    dot = np.zeros((8, 8))
    dot[3, 5] = 1
    np.testing.assert_array_equal(count_pixels(dot, [4, 2, 1]), [1, 1, 1])
    assert box_counting_image(np.ones((16, 16)), coarsest=2).dimension == pytest.approx(2)


def test_a_segment_has_dimension_one_from_points_and_image():
    t = np.linspace(-0.4, 0.4, 200_001)
    assert box_counting_points(np.stack([t, 0.3 * t], 1), finest=256).dimension == pytest.approx(1, abs=0.02)
    image = np.zeros((128, 128))
    image[64, 10:120] = 1
    assert box_counting_image(image, coarsest=4).dimension == pytest.approx(1, abs=0.05)


def test_box_counting_on_the_triangle_is_near_its_similarity_dimension():
    """At a test's size (200,000 points, boxes to 1/256) within 0.03; the lesson's sizes: benchmarks/measures.py."""
    ifs = ifslib.patterns.sierpinski_triangle()
    fit = box_counting_points(ifslib.chaos_game(ifs, 200_000), finest=256, offsets=2)
    assert fit.dimension == pytest.approx(ifs_similarity_dimension(ifs), abs=0.03)


def test_overlapping_copies_fall_below_the_similarity_dimension():
    """Three maps of scale 1/2 along a segment: Moran says log 3 / log 2, the attractor is the segment (1)."""
    maps = [[[0.5, 0, s], [0, 0.5, 0]] for s in (-0.2, 0.0, 0.2)]
    ifs = ifslib.patterns.affine(maps, primitive="segment")
    assert ifs_similarity_dimension(ifs) == pytest.approx(math.log(3) / math.log(2), abs=1e-6)
    fit = box_counting_points(ifslib.chaos_game(ifs, 100_000), finest=256, offsets=2)
    assert fit.dimension == pytest.approx(1, abs=0.05)  # 0.967: the coarsest boxes count a segment's ends short
    assert fit.dimension + 0.5 < ifs_similarity_dimension(ifs)


@pytest.mark.parametrize("call, message", [
    (lambda: similarity_dimension([]), "at least one scale"),
    (lambda: similarity_dimension([0.5, 1.0]), "strictly between 0 and 1"),
    (lambda: fit_box_dimension([0.5], [3]), "length >= 2"),
    (lambda: fit_box_dimension([0.5, 0.25], [3, 0]), "count >= 1"),
    (lambda: fit_box_dimension([0.5, 0.5], [3, 4]), "differ"),
    (lambda: box_counting_points(np.zeros((0, 2))), "non-empty"),
    (lambda: box_counting_image(np.zeros((16, 16))), "at least one lit pixel"),
    (lambda: box_counting_image(np.ones((12, 12)), finest=8), "whole pixels"),
    (lambda: box_counting_image(np.ones((8, 4))), "square"),
])
def test_bad_input(call, message):
    with pytest.raises(ifslib.IFSError, match=message):
        call()
