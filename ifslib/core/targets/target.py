"""Targets: images, arrays or IFSs turned into a binary mask on the pixel grid, with its distances.

Reading a file (which part is the figure) is `ifslib.core.targets.image`.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from scipy import ndimage
from skimage.transform import resize

from ...data import path as data_path
from ..geometry.leaves import check_bytes
from ..raster.distance import check_size
from ..raster.nearest import pixel_centres
from ..raster.render import figure_mask
from ...errors import IFSError
from ..geometry.ifs import IFS
from .image import check_threshold, file_polarity, read_image, resample_gray, threshold_gray




# Rough peak bytes per target pixel while a target is made (resampled gray levels, the mask, the
# distance transform and its float64 intermediates, the float32 copies kept), rounded up.
_TARGET_BYTES_PER_PIXEL = 64

# 16-bit modes, whose values Pillow's conversion to 8 bits would clip: read as 32-bit integers instead.


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
    polarity : str
        Which part of the source is the figure, and why, in words: e.g. ``"a dark figure on a light
        background (its border is light: 97 % of it)"`` (docs/guide/conventions.md).
    inverted : bool
        True when the figure is the source's dark (or transparent, or low) part.
    """

    mask: np.ndarray
    distance: torch.Tensor
    image: torch.Tensor
    name: str = ""
    gray: np.ndarray | None = None
    polarity: str = ""
    inverted: bool = False

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


def _check_invert(invert) -> bool | None:
    if invert is None or isinstance(invert, (bool, np.bool_)):
        return None if invert is None else bool(invert)
    raise IFSError(f"invert must be True (the figure is the dark part), False (the light part) or None "
                   f"(found from the image's border), got {invert!r}")




def _check_memory(size: int) -> None:
    check_bytes(size * size * _TARGET_BYTES_PER_PIXEL, f"a {size:,}x{size:,} target", "choose a smaller size")


















def target_from_mask(mask: np.ndarray, name: str = "", gray: np.ndarray | None = None, *, polarity: str = "",
                     inverted: bool = False) -> Target:
    """A `Target` from a square boolean mask (checks it is neither empty nor full), with its source's gray levels.

    ``polarity`` and ``inverted`` are recorded on the target (`Target.polarity`).
    """
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim != 2 or mask.shape[0] != mask.shape[1]:
        raise IFSError(f"a target mask must be square, got shape {mask.shape}")
    taken = f"; it was read as {polarity}" if polarity else ""
    if not mask.any():
        raise IFSError(f"the target {name or 'mask'} has no foreground pixel (empty mask){taken}; "
                       "invert=True takes the dark part as the figure, invert=False the light part")
    if mask.all():
        raise IFSError(f"the target {name or 'mask'} is all foreground{taken}; "
                       "invert=True takes the dark part as the figure, invert=False the light part")
    size = mask.shape[0]
    dist = ndimage.distance_transform_edt(~mask) / size
    gray = None if gray is None else np.asarray(gray, dtype=np.float32)
    return Target(mask, torch.from_numpy(dist.astype(np.float32)), torch.from_numpy(mask.astype(np.float32)), name, gray,
                  polarity, bool(inverted))


def _from_gray(gray: np.ndarray, size: int, invert: bool, threshold: float | None, name: str, polarity: str) -> Target:
    picture = resample_gray(gray, size, invert)
    mask = threshold_gray(picture, threshold)
    # shown at full contrast: resampling a thin line down dims it (the threshold is relative too)
    return target_from_mask(mask, name, picture / picture.max() if picture.max() > 0 else picture,
                            polarity=polarity, inverted=invert)




def load_target(source, size: int, invert: bool | None = None, threshold: float | None = None,
                depth: int | None = None) -> Target:
    """Make a fitting target from an image file, an array or an IFS.

    Parameters
    ----------
    source : str, path, numpy.ndarray, torch.Tensor or IFS
        An image file (PNG, GIF, JPEG, ...; 1-bit, gray, 16-bit, RGB, RGBA or palette), a name of
        one of the paper's images (``"koch"``, ``"sierpinski"``, ``"apple"``, ``"flower"``, see
        `ifslib.data`), a 2-D array (figure high), or an IFS (rendered at ``size``, figure where the
        render is >= 0.5).
    size : int
        Pixels per side of the target.
    invert : bool, optional
        None (the default): an image file's figure is found from its border, or its alpha channel
        (docs/guide/conventions.md); an array's figure is where it is high, an IFS's is its drawing.
        True: the figure is the dark (transparent, low) part; False: the light (opaque, high) part.
    threshold : float, optional
        Gray level in ``[0, 1]`` of the image's range above which a pixel is figure (0.5).
    depth : int, optional
        Depth at which to render an IFS source.

    Returns
    -------
    Target
        With `Target.polarity` saying which part was taken as the figure, and why.

    Raises
    ------
    IFSError
        Missing file, not an image, uniform image, a size over the memory budget, or an empty or
        all-foreground mask.
    """
    size = check_size(size)
    invert = _check_invert(invert)
    check_threshold(threshold)
    _check_memory(size)
    if isinstance(source, IFS):
        mask = figure_mask(source, size, depth)
        polarity = "the IFS's background, as asked (invert=True)" if invert else "the IFS's drawing"
        return target_from_mask(~mask if invert else mask, source.name or "ifs", polarity=polarity, inverted=bool(invert))
    if isinstance(source, torch.Tensor):
        source = source.detach().cpu().numpy()
    if isinstance(source, np.ndarray):
        polarity = ("where the array is low, as asked (invert=True)" if invert
                    else "where the array is high (an array is taken as it is)")
        return _from_gray(source, size, bool(invert), threshold, "array", polarity)
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.exists() and not path.suffix and str(source) in ("koch", "sierpinski", "apple", "flower"):
            path = data_path(str(source))
        gray, kind = read_image(path, size)
        invert, polarity = file_polarity(gray, kind, invert, threshold)
        return _from_gray(gray, size, invert, threshold, path.stem, polarity)
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
    """The same target at another size, made from the target's own gray levels.

    The picture (`Target.picture`) is resampled with scikit-image's ``resize``: bilinear, after a
    Gaussian blur against aliasing when shrinking (not an area mean), then thresholded at half its
    largest value, so a thin curve stays connected at a coarse size and a filled shape keeps its
    area. (`load_target` resamples an image file with Pillow's bilinear filter instead, so the two
    need not give the same mask.)

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
    return target_from_mask(threshold_gray(gray), target.name, gray, polarity=target.polarity, inverted=target.inverted)


def foreground_points(target: Target) -> np.ndarray:
    """Plane coordinates ``(k, 2)`` of the target's foreground pixel centres."""
    x, y = pixel_centres(target.size)
    flat = torch.from_numpy(target.mask.reshape(-1))
    return torch.stack([x[flat], y[flat]], 1).numpy()


def sample_foreground(target: Target, n: int, rng: np.random.Generator | int = 0) -> np.ndarray:
    """At most ``n`` of the target's foreground pixel centres ``(min(n, k), 2)``, drawn without replacement
    by ``rng`` (a generator, or the seed of one); all of them, in order, when there are no more than ``n``."""
    fg = foreground_points(target)
    if len(fg) <= n:
        return fg
    rng = np.random.default_rng(rng) if isinstance(rng, (int, np.integer)) else rng
    return fg[rng.choice(len(fg), n, replace=False)]

