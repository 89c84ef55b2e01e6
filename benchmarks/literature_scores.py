"""The literature's scores of a drawing against a target: PSNR, SSIM, and the F1 and IoU of their masks,
after cropping a border, as Djeacoumar et al. ("Learning Image Fractals Using Chaotic Differentiable
Point Splatting", CGF 2025) score fractal inversions.

Their evaluation (``base/scripts/compute_metrics.py`` in github.com/sshadr/chaotic-fractals) removes
``int(0.125 * res)`` pixels from *each* side of a ``res x res`` image, 128 of 1024, and scores the
middle 768 x 768: their fractals are scaled to span 75 % of the image (``apply_mv_transform``: a
padding of 12.5 % a side), so the crop removes the empty padding. Then per image: PSNR
``10 log10(1 / MSE)`` on intensities in [0, 1]; SSIM with an 11-pixel Gaussian window of sigma 1.5
and K1 = 0.01, K2 = 0.03 (Wang et al. 2004); F1 and IoU of the masks ``image > 0``; averaged over
the images; and LPIPS (AlexNet), which this module does not compute (it needs a network's weights).
"""
from __future__ import annotations

import math

import numpy as np
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

from ifslib.errors import IFSError
from ifslib.core.scoring.metrics import f1, iou

#: The share of each side the literature crops before scoring.
LITERATURE_CROP = 0.125

#: SSIM's Gaussian window: sigma 1.5 pixels, truncated at 3.5 sigma, so 11 pixels wide (as theirs).
SSIM_SIGMA = 1.5
SSIM_WINDOW = 2 * int(3.5 * SSIM_SIGMA + 0.5) + 1


def crop_border(image: np.ndarray, crop: float = LITERATURE_CROP) -> np.ndarray:
    """The image without ``int(crop * side)`` pixels on each of its four sides.

    Parameters
    ----------
    image : numpy.ndarray
        ``(h, w)``.
    crop : float
        Share of each side removed from each end, in [0, 0.5): 0.125 of 256 removes 32 rows at the
        top, 32 at the bottom, 32 columns at the left and 32 at the right, leaving the middle 192².

    Returns
    -------
    numpy.ndarray
        ``(h - 2 int(crop h), w - 2 int(crop w))``, a view.
    """
    if isinstance(crop, bool) or not isinstance(crop, (int, float)) or not 0 <= crop < 0.5:
        raise IFSError(f"crop is the share of each side removed from each end, in [0, 0.5); got {crop!r}")
    rows, cols = int(crop * image.shape[0]), int(crop * image.shape[1])
    return image[rows:image.shape[0] - rows, cols:image.shape[1] - cols]


def _as_image(image, name: str) -> np.ndarray:
    """``image`` as a float64 ``(h, w)`` array in [0, 1] (a mask gives 0 and 1), or `IFSError`."""
    array = np.asarray(image)
    if array.ndim != 2:
        raise IFSError(f"{name} must be one gray image or mask of shape (h, w), got shape {array.shape}")
    if array.dtype == bool:
        return array.astype(np.float64)
    if not np.issubdtype(array.dtype, np.number):
        raise IFSError(f"{name} must hold numbers in [0, 1] or booleans, got dtype {array.dtype}")
    array = array.astype(np.float64)
    if not np.isfinite(array).all():
        raise IFSError(f"{name} must hold finite intensities in [0, 1], got NaN or infinite values")
    if array.min() < 0 or array.max() > 1:
        raise IFSError(f"{name} must hold intensities in [0, 1] (divide 8-bit images by 255), "
                       f"got values from {array.min():.4g} to {array.max():.4g}")
    return array


def literature_scores(drawn, target, crop: float = LITERATURE_CROP, threshold: float = 0.5) -> dict[str, float]:
    """PSNR, SSIM, F1 and IoU of a drawing against a target of the same size, after cropping the border.

    Parameters
    ----------
    drawn, target : array-like
        ``(h, w)`` gray images in [0, 1] or boolean masks.
    crop : float
        Share of each side removed from each end before scoring (`crop_border`): 0.125 as in
        Djeacoumar et al., where the fractal spans the middle 75 %.
    threshold : float
        A pixel is on a mask where its intensity is ``>= threshold`` (0.5: ifslib's masks, where the
        render is ``>= 0.5``). Djeacoumar et al. take every pixel ``> 0`` of their point splats.

    Returns
    -------
    dict
        ``psnr`` (dB, ``inf`` when the cropped images are equal), ``ssim`` (skimage's
        `structural_similarity` with their window and constants; it averages the SSIM map without its
        5-pixel rim, where theirs zero-pads), ``f1`` and ``iou`` of the masks (1 when both are empty).

    Raises
    ------
    IFSError
        On images of other shapes than ``(h, w)``, of different sizes, with values outside [0, 1],
        a crop outside [0, 0.5), a threshold outside (0, 1], or fewer than 11 pixels a side left for SSIM's window.
    """
    drawn, target = _as_image(drawn, "drawn"), _as_image(target, "target")
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float)) or not 0 < threshold <= 1:
        raise IFSError(f"threshold is the intensity from which a pixel is on the mask, in (0, 1]; got {threshold!r}")
    if drawn.shape != target.shape:
        raise IFSError(f"drawn and target must be the same size, got {drawn.shape} and {target.shape}")
    drawn, target = crop_border(drawn, crop), crop_border(target, crop)
    if min(drawn.shape) < SSIM_WINDOW:
        raise IFSError(f"after the crop {drawn.shape} pixels are left: SSIM needs at least {SSIM_WINDOW} a side "
                       "(score larger images, or crop less)")
    mse = float(np.mean((drawn - target) ** 2))
    psnr = math.inf if mse == 0 else float(peak_signal_noise_ratio(target, drawn, data_range=1.0))
    ssim = float(structural_similarity(target, drawn, data_range=1.0, gaussian_weights=True, sigma=SSIM_SIGMA,
                                       use_sample_covariance=False))
    on_drawn, on_target = drawn >= threshold, target >= threshold
    return {"psnr": psnr, "ssim": ssim, "f1": f1(on_drawn, on_target), "iou": iou(on_drawn, on_target)}


__all__ = ["LITERATURE_CROP", "crop_border", "literature_scores"]
