"""Targets: images, arrays or IFSs turned into a binary mask on the pixel grid, with its distances."""
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


@dataclass
class Target:
    """A fitting target on the ``size x size`` grid: its ``mask``, the distance to it (plane units), the mask as an
    ``image``, the source's ``gray`` levels, and which part of the source is the figure (``polarity``), and why."""

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
        """The target as a reader recognises it, figure bright: the source's gray levels when it had them (a thin
        anti-aliased line thresholded at mid-range looks dotted), else the mask."""
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
    """A `Target` from a square boolean mask, neither empty nor full, with its source's gray levels."""
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
    """A fitting target of ``size`` pixels from an image file, one of the paper's images by name, an array (figure high)
    or an IFS; ``invert`` None reads the figure from the border (docs/guide/conventions.md)."""
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
    """The sizes of a target's resolution pyramid, coarsest first: ``size`` halved while it stays >= ``coarsest``,
    every other one kept with ``factor=4`` (``pyramid_sizes(1024, 64, 4) == [64, 256, 1024]``)."""
    size, coarsest = check_size(size), check_size(coarsest)
    if factor not in (2, 4):
        raise IFSError(f"factor must be 2 or 4, got {factor!r}")
    sizes = [size]
    while sizes[0] // 2 >= coarsest:
        sizes.insert(0, sizes[0] // 2)
    kept = sizes[::factor // 2]
    return kept if kept[-1] == size else kept + [size]


def resize_target(target: Target, size: int) -> Target:
    """The same target at another size, from its own gray levels (`Target.picture`): scikit-image's anti-aliased
    ``resize``, thresholded at half its largest value, so a thin curve stays connected at a coarse size."""
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
