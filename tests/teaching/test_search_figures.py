"""The figures of the lessons that find maps (07, 08, 11): a target's copies under maps, an attractor over a target, the
price of maps, two masks over each other."""
import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from ifslib.teaching import search_figures  # noqa: E402
from ifslib.core.targets.target import target_from_mask  # noqa: E402


@pytest.fixture
def square():
    """A 16 x 16 target whose figure is a 4 x 4 block of pixels (rows and columns 6-9)."""
    mask = np.zeros((16, 16), bool)
    mask[6:10, 6:10] = True
    return target_from_mask(mask, "square")


IDENTITY = np.array([[[1.0, 0, 0], [0, 1.0, 0]]])


def test_copies_image_of_the_identity_tints_exactly_the_figure(square):
    image = search_figures.copies_image(IDENTITY, square)
    expected = 0.5 * 0.3 + 0.5 * np.array(search_figures.COPY_COLOURS[0])
    assert image.shape == (16, 16, 3)
    assert np.allclose(image[square.mask], expected)
    assert np.all(image[~square.mask] == 0)


def test_copies_image_moves_a_copy_by_its_translation(square):
    # two maps: the identity and a shift of two pixels to the right (2/16 plane units)
    shifted = np.array([[[1.0, 0, 0], [0, 1.0, 0]], [[1.0, 0, 2 / 16], [0, 1.0, 0]]])
    image = search_figures.copies_image(shifted, square)
    second = np.zeros((16, 16), bool)
    second[6:10, 8:12] = True
    first_only, both, second_only = square.mask & ~second, square.mask & second, second & ~square.mask
    c0, c1 = (np.array(c) for c in search_figures.COPY_COLOURS[:2])
    assert np.allclose(image[first_only], 0.5 * 0.3 + 0.5 * c0)
    assert np.allclose(image[both], 0.5 * (0.5 * 0.3 + 0.5 * c0) + 0.5 * c1)   # blended twice
    assert np.allclose(image[second_only], 0.5 * c1)                              # off the figure
    assert np.all(image[~(square.mask | second)] == 0)


def test_copies_image_gives_ten_copies_ten_colours(square):
    # ten copies shrunk to a pixel each, in a row above the figure: ten colours (tab10), none repeated
    maps = np.array([[[1 / 16, 0, (k - 4.5) / 16], [0, 1 / 16, 0.3]] for k in range(10)])
    image = search_figures.copies_image(maps, square)
    row = image[np.rint((0.5 - 0.3) * 16 - 0.5).astype(int)]
    assert len({tuple(np.round(c, 6)) for c in row if c.any()}) == 10


def test_copies_image_drops_what_lands_outside_the_frame(square):
    far = np.array([[[1.0, 0, 2.0], [0, 1.0, 0]]])   # the copy lies two frames to the right
    image = search_figures.copies_image(far, square)
    assert np.allclose(image[square.mask], 0.3) and np.all(image[~square.mask] == 0)


def test_show_attractor_draws_chaos_game_points_on_the_attractor(square):
    # one map x -> x/2 + c has the single point 2c as its attractor
    c = np.array([0.05, -0.1])
    maps = np.array([[[0.5, 0, c[0]], [0, 0.5, c[1]]]])
    fig, ax = plt.subplots()
    points = search_figures.show_attractor(ax, maps, square, "one point", points=500)
    plt.close(fig)
    assert points.shape == (500, 2)
    assert np.allclose(points, 2 * c, atol=1e-12)


def test_price_bars_stack_misfit_and_price():
    table = [{"maps": 2, "iou": 0.80}, {"maps": 3, "iou": 0.95}, {"maps": 4, "iou": 0.96}]
    fig, ax = plt.subplots()
    heights = search_figures.price_bars(ax, table, 0.04, chosen=3)
    bars = [p for p in ax.patches]
    plt.close(fig)
    assert np.allclose(heights, [0.2 + 0.08, 0.05 + 0.12, 0.04 + 0.16])
    assert int(np.argmin(heights)) == 1   # the chosen number scores least here
    # 3 misfit bars, 3 price bars on top of them, one outline for the chosen
    assert len(bars) == 7
    assert np.allclose([b.get_height() for b in bars[:3]], [0.2, 0.05, 0.04])
    assert np.allclose([b.get_y() for b in bars[3:6]], [0.2, 0.05, 0.04])
    assert bars[6].get_x() + bars[6].get_width() / 2 == pytest.approx(3)


def test_overlay_colours_each_pixel_by_the_masks_that_hold_it():
    target = np.array([[True, True], [False, False]])
    other = np.array([[True, False], [True, False]])
    image = search_figures.overlay(other, target)
    assert np.array_equal(image[0, 0], [1.0, 1.0, 1.0])     # both
    assert np.array_equal(image[0, 1], [0.2, 0.5, 1.0])     # the target's only
    assert np.array_equal(image[1, 0], [1.0, 0.5, 0.0])     # the other's only
    assert np.array_equal(image[1, 1], [0.0, 0.0, 0.0])     # neither
