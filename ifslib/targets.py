"""Targets: images, arrays or IFSs turned into a binary mask on the pixel grid, with its distances.

Foreground is the figure: white on black, as in the paper's files. A dark-on-light image needs
``invert=True``; nothing is guessed. Gray levels are thresholded at the middle of the image's own
range, ``(min + max) / 2``, because the paper's images are anti-aliased (the Koch curve peaks at
194 of 255), or at an explicit ``threshold`` in ``[0, 1]``.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from PIL import Image, UnidentifiedImageError
from scipy import ndimage

from .distance import check_size
from .errors import IFSError
from .ifs import IFS


@dataclass
class Target:
    """A fitting target on the ``size x size`` pixel grid.

    Attributes
    ----------
    mask : numpy.ndarray
        ``(size, size)`` bool, True on the figure.
    distance : torch.Tensor
        ``(size, size)`` float32: distance from each pixel centre to the nearest figure pixel centre,
        in plane units (0 on the figure), from `scipy.ndimage.distance_transform_edt`.
    image : torch.Tensor
        ``(size, size)`` float32 in ``[0, 1]``: the mask as pixels.
    name : str
        Where it came from.
    """

    mask: np.ndarray
    distance: torch.Tensor
    image: torch.Tensor
    name: str = ""

    @property
    def size(self) -> int:
        return self.mask.shape[0]


def _read_image(path: Path) -> np.ndarray:
    if not path.is_file():
        raise IFSError(f"no image file at {str(path)!r}")
    try:
        with Image.open(path) as im:
            im.load()
            if im.mode in ("RGBA", "LA", "PA") or (im.mode == "P" and "transparency" in im.info):
                im = im.convert("RGBA")
                rgba = np.asarray(im, dtype=np.float64) / 255
                gray = rgba[..., :3].mean(-1) * rgba[..., 3]  # transparent counts as black background
            else:
                gray = np.asarray(im.convert("L"), dtype=np.float64) / 255
    except (UnidentifiedImageError, OSError) as exc:
        raise IFSError(f"{str(path)!r} is not an image this library can read (PNG, GIF, JPEG): {exc}") from None
    return gray


def mask_from_gray(gray: np.ndarray, size: int, invert: bool = False, threshold: float | None = None) -> np.ndarray:
    """Resample a gray image to ``size x size`` and threshold it to a figure mask.

    Parameters
    ----------
    gray : numpy.ndarray
        ``(h, w)`` values; scaled to ``[0, 1]`` by the image's own range.
    size : int
    invert : bool
        True for a dark figure on a light background.
    threshold : float, optional
        In ``[0, 1]`` of the image's range; 0.5 (mid-range) by default.
    """
    gray = np.asarray(gray, dtype=np.float64)
    if gray.ndim != 2 or min(gray.shape) == 0:
        raise IFSError(f"a target array must be 2-D and non-empty, got shape {gray.shape}")
    if not np.isfinite(gray).all():
        raise IFSError("a target array holds values that are not finite (NaN or inf)")
    lo, hi = gray.min(), gray.max()
    if hi <= lo:
        raise IFSError("the target image is uniform: its mask would be empty or all foreground")
    gray = (gray - lo) / (hi - lo)
    if invert:
        gray = 1 - gray
    if gray.shape != (size, size):
        gray = np.asarray(Image.fromarray(gray.astype(np.float32), mode="F").resize((size, size), Image.BILINEAR))
    t = 0.5 if threshold is None else float(threshold)
    if not 0 < t < 1:
        raise IFSError(f"threshold must lie strictly between 0 and 1, got {threshold!r}")
    return gray >= t * gray.max() if gray.max() > 0 else gray > 0


def target_from_mask(mask: np.ndarray, name: str = "") -> Target:
    """A `Target` from a square boolean mask (checks it is neither empty nor full)."""
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2 or mask.shape[0] != mask.shape[1]:
        raise IFSError(f"a target mask must be square, got shape {mask.shape}")
    if not mask.any():
        raise IFSError(f"the target {name or 'mask'} has no foreground pixel (empty mask); "
                       "is it a dark figure on white? then pass invert=True")
    if mask.all():
        raise IFSError(f"the target {name or 'mask'} is all foreground; is it a dark figure on white? then pass invert=True")
    size = mask.shape[0]
    dist = ndimage.distance_transform_edt(~mask) / size
    return Target(mask, torch.from_numpy(dist.astype(np.float32)), torch.from_numpy(mask.astype(np.float32)), name)


def load_target(source, size: int, invert: bool = False, threshold: float | None = None, depth: int | None = None) -> Target:
    """Make a fitting target from an image file, an array or an IFS.

    Parameters
    ----------
    source : str, path, numpy.ndarray, torch.Tensor or IFS
        An image file (PNG, GIF, JPEG; gray, RGB, RGBA or palette), a name of one of the paper's
        images (``"koch"``, ``"sierpinski"``, ``"apple"``, ``"flower"``, see `ifslib.data`), a 2-D
        array (figure high), or an IFS (rendered at ``size``, figure where the render is >= 0.5).
    size : int
        Pixels per side of the target.
    invert : bool
        True for a dark figure on a light background.
    threshold : float, optional
        Gray level in ``[0, 1]`` of the image's range above which a pixel is figure (0.5).
    depth : int, optional
        Depth at which to render an IFS source.

    Returns
    -------
    Target

    Raises
    ------
    IFSError
        Missing file, not an image, uniform image, or an empty or all-foreground mask.
    """
    size = check_size(size)
    if isinstance(source, IFS):
        from .render import figure_mask

        mask = figure_mask(source, size, depth)
        return target_from_mask(~mask if invert else mask, source.name or "ifs")
    if isinstance(source, torch.Tensor):
        source = source.detach().cpu().numpy()
    if isinstance(source, np.ndarray):
        return target_from_mask(mask_from_gray(source, size, invert, threshold), "array")
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.exists() and not path.suffix and str(source) in ("koch", "sierpinski", "apple", "flower"):
            from .data import path as data_path

            path = data_path(str(source))
        return target_from_mask(mask_from_gray(_read_image(path), size, invert, threshold), path.stem)
    raise IFSError(f"cannot make a target from a {type(source).__name__}: give an image path, an array or an IFS")
