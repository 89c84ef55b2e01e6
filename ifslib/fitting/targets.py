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
from skimage.transform import resize

from ..data import path as data_path
from ..raster.distance import check_size
from ..raster.nearest import pixel_centres
from ..raster.render import figure_mask
from ..errors import IFSError
from ..geometry.ifs import IFS


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
    gray : numpy.ndarray, optional
        ``(size, size)`` float in ``[0, 1]``: the source image's own gray levels at this size, figure
        bright, before thresholding (None for a mask or an IFS source). See `picture`.
    """

    mask: np.ndarray
    distance: torch.Tensor
    image: torch.Tensor
    name: str = ""
    gray: np.ndarray | None = None

    @property
    def size(self) -> int:
        return self.mask.shape[0]

    @property
    def picture(self) -> np.ndarray:
        """The target as a reader recognises it: ``(size, size)`` in ``[0, 1]``, figure bright.

        The source's gray levels when it had them, else the mask. A thin anti-aliased line
        (the paper's Koch file) thresholded at mid-range keeps only its brightest pixels and looks
        dotted; its gray levels show the curve the file draws.
        """
        return self.gray if self.gray is not None else self.mask.astype(np.float32)


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


def resample_gray(gray: np.ndarray, size: int, invert: bool = False) -> np.ndarray:
    """Scale a gray image to ``[0, 1]`` by its own range, figure bright, and resample it to ``size x size``.

    Parameters
    ----------
    gray : numpy.ndarray
        ``(h, w)`` values.
    size : int
    invert : bool
        True for a dark figure on a light background.

    Returns
    -------
    numpy.ndarray
        ``(size, size)`` float, bilinear resampling (Pillow).
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
    return gray


def threshold_gray(gray: np.ndarray, threshold: float | None = None) -> np.ndarray:
    """The figure mask of a `resample_gray` image: at least ``threshold`` (0.5) of its largest value."""
    t = 0.5 if threshold is None else float(threshold)
    if not 0 < t < 1:
        raise IFSError(f"threshold must lie strictly between 0 and 1, got {threshold!r}")
    return gray >= t * gray.max() if gray.max() > 0 else gray > 0


def target_from_mask(mask: np.ndarray, name: str = "", gray: np.ndarray | None = None) -> Target:
    """A `Target` from a square boolean mask (checks it is neither empty nor full), with its source's gray levels."""
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
    gray = None if gray is None else np.asarray(gray, dtype=np.float32)
    return Target(mask, torch.from_numpy(dist.astype(np.float32)), torch.from_numpy(mask.astype(np.float32)), name, gray)


def _from_gray(gray: np.ndarray, size: int, invert: bool, threshold: float | None, name: str) -> Target:
    picture = resample_gray(gray, size, invert)
    mask = threshold_gray(picture, threshold)
    # shown at full contrast: resampling a thin line down dims it (the threshold is relative too)
    return target_from_mask(mask, name, picture / picture.max() if picture.max() > 0 else picture)


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
        mask = figure_mask(source, size, depth)
        return target_from_mask(~mask if invert else mask, source.name or "ifs")
    if isinstance(source, torch.Tensor):
        source = source.detach().cpu().numpy()
    if isinstance(source, np.ndarray):
        return _from_gray(source, size, invert, threshold, "array")
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.exists() and not path.suffix and str(source) in ("koch", "sierpinski", "apple", "flower"):
            path = data_path(str(source))
        return _from_gray(_read_image(path), size, invert, threshold, path.stem)
    raise IFSError(f"cannot make a target from a {type(source).__name__}: give an image path, an array or an IFS")


def pyramid_sizes(size: int, coarsest: int = 64, factor: int = 2) -> list[int]:
    """The sizes of a target's resolution pyramid, coarsest first.

    ``size`` is halved while it stays >= ``coarsest``; with ``factor=4`` every other of those sizes
    is kept (the coarsest and the full size always). ``pyramid_sizes(256, 64) == [64, 128, 256]``,
    ``pyramid_sizes(1024, 64, 4) == [64, 256, 1024]``; a target smaller than ``2 * coarsest`` is its
    own pyramid (``[size]``).
    """
    size, coarsest = check_size(size), check_size(coarsest)
    if factor not in (2, 4):
        raise IFSError(f"factor must be 2 or 4, got {factor!r}")
    sizes = [size]
    while sizes[0] // 2 >= coarsest:
        sizes.insert(0, sizes[0] // 2)
    kept = sizes[::factor // 2]
    return kept if kept[-1] == size else kept + [size]


def resize_target(target: Target, size: int) -> Target:
    """The same target at another size, as `load_target` would make it from the target's own gray levels.

    The picture (`Target.picture`) is resampled with scikit-image (area-weighted: anti-aliased when
    shrinking) and thresholded at half its largest value, so a thin curve stays connected at a
    coarse size and a filled shape keeps its area.

    Parameters
    ----------
    target : Target
    size : int
        Pixels per side.

    Returns
    -------
    Target
        ``target`` itself when ``size == target.size``.
    """
    size = check_size(size)
    if size == target.size:
        return target
    gray = resize(target.picture.astype(np.float64), (size, size), anti_aliasing=size < target.size)
    gray = np.clip(gray, 0, None)
    if gray.max() <= 0:
        raise IFSError(f"the target {target.name!r} vanishes at {size}x{size} pixels")
    gray = gray / gray.max()
    return target_from_mask(threshold_gray(gray), target.name, gray)


def foreground_points(target: Target) -> np.ndarray:
    """Plane coordinates ``(k, 2)`` of the target's foreground pixel centres."""
    x, y = pixel_centres(target.size)
    flat = torch.from_numpy(target.mask.reshape(-1))
    return torch.stack([x[flat], y[flat]], 1).numpy()
