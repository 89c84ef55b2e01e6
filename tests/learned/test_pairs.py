"""Training pairs: the picture is the maps' attractor, on the library's pixel grid, and a symmetry of the frame
turns the maps with the picture."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib.learned import config
from ifslib.learned.pairs import SYMMETRIES, chaos_points, pair, picture, turned


def test_pixels_hold_the_library_pixel_centres():
    x, y = ifslib.pixel_centres(8)
    image = picture(np.stack([x.numpy(), y.numpy()], 1)[[0, 9, 63]], 8)
    assert np.argwhere(image).tolist() == [[0, 0], [1, 1], [7, 7]]


def iou(a, b):
    return (a & b).sum() / (a | b).sum()


def test_the_picture_is_the_maps_attractor_by_the_library_chaos_game():
    image, maps = pair(config.VALIDATION_TAG, 3)
    ifs = ifslib.patterns.affine(maps, depth=2)
    drawn = picture(ifslib.chaos_game(ifs, 200_000), config.SIZE)
    assert 2 <= len(maps) <= 10 and iou(image, drawn) > 0.8
    box = np.argwhere(image)
    assert (box.max(0) - box.min(0) + 1).max() == pytest.approx(config.EXTENT * config.SIZE, abs=2)


def test_pairs_are_seeded_and_apart_from_the_benchmarks_integer_seeds():
    a, b = pair(config.TRAIN_TAG, 7), pair(config.TRAIN_TAG, 7)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert not np.array_equal(pair(config.TRAIN_TAG, 7, maps=10)[1].shape, ifslib.random_fractals.random_ifs(10, 7).maps().shape) \
        or not np.allclose(pair(config.TRAIN_TAG, 7, maps=10)[1][:, :, :2],
                           ifslib.random_fractals.random_ifs(10, 7).maps()[:, :2, :2].numpy())


@pytest.mark.parametrize("k", range(8))
def test_a_symmetry_turns_the_picture_with_the_maps(k):
    image, maps = pair(config.VALIDATION_TAG, 11)
    seen, moved = turned(image, maps, SYMMETRIES[k])
    drawn = picture(chaos_points(moved, np.random.default_rng(0), 2000, 100), config.SIZE)
    assert seen.sum() == image.sum() and iou(seen, drawn) > 0.7
