"""literature_scores: PSNR, SSIM, F1 and IoU after cropping 12.5 % of each side, against hand computations."""
import math

import numpy as np
import pytest

from ifslib.errors import IFSError
from common_testing import benchmark_module

crop_border, literature_scores = benchmark_module("literature_scores").crop_border, benchmark_module("literature_scores").literature_scores


def figure(size=32, seed=0):
    """A gray image in [0, 1] with a mask-like blob in the middle."""
    rng = np.random.default_rng(seed)
    image = rng.uniform(0.0, 0.3, (size, size))
    image[10:22, 8:24] = rng.uniform(0.6, 1.0, (12, 16))
    return image


def test_identical_images_score_perfectly():
    image = figure()
    scores = literature_scores(image, image)
    assert scores["psnr"] == math.inf
    assert scores["ssim"] == pytest.approx(1.0)
    assert scores["f1"] == 1.0 and scores["iou"] == 1.0
    masks = literature_scores(image >= 0.5, image >= 0.5)
    assert masks == {"psnr": math.inf, "ssim": pytest.approx(1.0), "f1": 1.0, "iou": 1.0}


def test_a_small_case_by_hand():
    # 32 x 32, crop 4 px a side: the middle 24 x 24 = 576 pixels are scored
    target = np.zeros((32, 32))
    target[8:16, 8:16] = 1.0                      # 64 pixels on
    drawn = target.copy()
    drawn[8:16, 16:20] = 1.0                      # 32 more pixels on, all inside the crop
    scores = literature_scores(drawn, target)
    assert scores["psnr"] == pytest.approx(10 * math.log10(576 / 32))
    assert scores["iou"] == pytest.approx(64 / 96)
    assert scores["f1"] == pytest.approx(2 * 64 / (64 + 96))


def test_ssim_of_two_constant_images_by_hand():
    # means 1 and 0.5, no variance: SSIM = (2 mu1 mu2 + C1) / (mu1^2 + mu2^2 + C1), C1 = (0.01 * 1)^2
    c1 = 0.01 ** 2
    scores = literature_scores(np.full((32, 32), 0.5), np.ones((32, 32)))
    assert scores["ssim"] == pytest.approx((2 * 0.5 + c1) / (1.25 + c1))
    assert scores["psnr"] == pytest.approx(10 * math.log10(1 / 0.25))


def test_the_crop_is_of_each_side():
    image = np.zeros((256, 256))
    assert crop_border(image).shape == (192, 192)     # 32 rows and columns off each side
    assert crop_border(np.zeros((16, 40)), 0.125).shape == (12, 30)
    assert crop_border(image, 0).shape == (256, 256)


def test_differences_in_the_border_are_not_scored():
    target = figure(32)
    drawn = target.copy()
    drawn[:4] = 1 - drawn[:4]                     # the top 4 rows: cropped (int(0.125 * 32) = 4)
    drawn[:, -4:] = 1 - drawn[:, -4:]
    assert literature_scores(drawn, target)["psnr"] == math.inf
    uncropped = literature_scores(drawn, target, crop=0)
    assert uncropped["psnr"] < 10 and uncropped["iou"] < 1
    drawn[4, 10] = 1 - drawn[4, 10]               # the first row kept
    assert literature_scores(drawn, target)["psnr"] < math.inf


def test_the_threshold_makes_the_masks():
    target = np.zeros((32, 32))
    target[8:24, 8:24] = 0.4
    assert literature_scores(target, np.zeros((32, 32)))["iou"] == 1.0          # both empty at 0.5
    assert literature_scores(target, np.zeros((32, 32)), threshold=0.3)["iou"] == 0.0


@pytest.mark.parametrize("drawn, target, kwargs, words", [
    (np.zeros((32, 32)), np.zeros((32, 30)), {}, "same size"),
    (np.zeros((32, 32, 3)), np.zeros((32, 32, 3)), {}, "(h, w)"),
    (np.full((32, 32), 255.0), np.zeros((32, 32)), {}, "divide 8-bit"),
    (np.full((32, 32), np.nan), np.zeros((32, 32)), {}, "finite"),
    (np.zeros((32, 32)), np.zeros((32, 32)), {"crop": 0.5}, "[0, 0.5)"),
    (np.zeros((32, 32)), np.zeros((32, 32)), {"crop": -0.1}, "[0, 0.5)"),
    (np.zeros((32, 32)), np.zeros((32, 32)), {"threshold": 0}, "(0, 1]"),
    (np.zeros((12, 12)), np.zeros((12, 12)), {}, "at least 11"),
    (np.array([["a"] * 32] * 32), np.zeros((32, 32)), {}, "numbers"),
])
def test_bad_input_is_refused(drawn, target, kwargs, words):
    with pytest.raises(IFSError) as info:
        literature_scores(drawn, target, **kwargs)
    assert words in str(info.value)
