"""Targets: images, arrays or IFSs turned into a binary mask on the pixel grid, with its distances.

Which part of an image file is the figure
-----------------------------------------
The background is the colour that touches the image's border. The file's gray levels are scaled
to ``[0, 1]`` by their own range and the border band (its outermost ``1/32`` of the smaller side,
at least one pixel: a scan's thin dark edge does not outvote the page) is read
(`border_polarity`):

* mostly dark (under ``0.5 - SPLIT`` of its pixels at or above the threshold): the figure is the
  light part, as in the paper's files, whose borders are black;
* mostly light (over ``0.5 + SPLIT``): the figure is the dark part, as in most drawings;
* split between the two (a figure that touches much of the border): there is no majority to go
  by, the light part is taken, as in the paper's files, and `Target.polarity` says it is a guess.

An image with a transparent part (RGBA, LA, PA, or a palette or colour key with transparency, its
alpha not uniform) is read by its alpha channel: the figure is what is drawn, whatever its colour,
unless the alpha's own border is mostly opaque (rounded corners, a transparent hole): then the
transparency is not the background, and the colours, composited over white, are read as above.
An image opaque everywhere is read by its colours.

``invert=True`` takes the dark (or transparent) part as the figure and ``invert=False`` the light
(or opaque) part, whatever the border. Arrays and IFSs are not guessed: an array's figure is where
it is high, an IFS's is its drawing. `Target.polarity` says which part was taken and why; the
command line prints it, so that a fit of the background is never silent.

Gray levels are thresholded at the middle of the image's own range, ``(min + max) / 2``, because
the paper's images are anti-aliased (the Koch curve peaks at 194 of 255), or at an explicit
``threshold`` in ``[0, 1]``. 16-bit images are scaled by their own range too (Pillow's conversion to
8 bits would clip them). An image larger than `READ_SIDE` pixels a side (and than twice the target)
is reduced while it is read, so that memory stays bounded: the resampling to the target would
average those pixels anyway.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from PIL import Image, ImageOps, UnidentifiedImageError
from scipy import ndimage
from skimage.transform import resize

from ..data import path as data_path
from ..geometry.leaves import check_bytes
from ..raster.distance import check_size
from ..raster.nearest import pixel_centres
from ..raster.render import figure_mask
from ..errors import IFSError
from ..geometry.ifs import IFS

#: Half-width of the band around an even split in which a border has no majority (`border_polarity`).
SPLIT = 0.1

#: The border band's width as a fraction of the image's smaller side (at least one pixel).
BORDER_BAND = 1 / 32

#: Pixels a side above which an image is reduced as it is read (never below twice the target's size).
READ_SIDE = 2048

# Rough peak bytes per target pixel while a target is made (resampled gray levels, the mask, the
# distance transform and its float64 intermediates, the float32 copies kept), rounded up.
_TARGET_BYTES_PER_PIXEL = 64

# 16-bit modes, whose values Pillow's conversion to 8 bits would clip: read as 32-bit integers instead.
_WIDE_MODES = ("I;16", "I;16L", "I;16B", "I;16N")


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
        background (its border is light: 97 % of it)"`` (see the module docstring).
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


def _check_threshold(threshold) -> float:
    t = 0.5 if threshold is None else float(threshold)
    if not 0 < t < 1:
        raise IFSError(f"threshold must lie strictly between 0 and 1, got {threshold!r}")
    return t


def _check_memory(size: int) -> None:
    check_bytes(size * size * _TARGET_BYTES_PER_PIXEL, f"a {size:,}x{size:,} target", "choose a smaller size")


def _scaled(gray: np.ndarray) -> np.ndarray:
    """``gray`` as float64 scaled to ``[0, 1]`` by its own range, after checking it is a non-uniform 2-D array."""
    gray = np.asarray(gray, dtype=np.float64)
    if gray.ndim != 2 or min(gray.shape) == 0:
        raise IFSError(f"a target array must be 2-D and non-empty, got shape {gray.shape}")
    if not np.isfinite(gray).all():
        raise IFSError("a target array holds values that are not finite (NaN or inf)")
    lo, hi = gray.min(), gray.max()
    if hi <= lo:
        raise IFSError("the target image is uniform (one gray level everywhere): there is no figure to fit")
    return (gray - lo) / (hi - lo)


def border_band(shape: tuple[int, int]) -> np.ndarray:
    """The border band of an image of ``shape``: a bool array, True on its outermost `BORDER_BAND` (at least one pixel)."""
    h, w = shape
    width = max(1, round(min(h, w) * BORDER_BAND))
    band = np.ones((h, w), dtype=bool)
    band[width:h - width, width:w - width] = False
    return band


def _percent(share: float) -> str:
    return f"{round(100 * share)} %"


def border_polarity(gray: np.ndarray, threshold: float | None = None) -> tuple[bool, str]:
    """Which part of an image is the figure, read from its border: the background is what touches it.

    Parameters
    ----------
    gray : numpy.ndarray
        ``(h, w)`` gray levels of any range (not uniform).
    threshold : float, optional
        Gray level in ``(0, 1)`` of the image's range at or above which a pixel is light (0.5, the
        mask's threshold).

    Returns
    -------
    invert : bool
        True when the figure is the dark part: more than ``0.5 + SPLIT`` of the border band is light.
        A split border (within `SPLIT` of an even split) gives False, the paper's convention.
    polarity : str
        The part taken and why, for `Target.polarity`.
    """
    light = float((_scaled(gray)[border_band(np.shape(gray))] >= _check_threshold(threshold)).mean())
    if light > 0.5 + SPLIT:
        return True, f"a dark figure on a light background (its border is light: {_percent(light)} of it)"
    if light < 0.5 - SPLIT:
        return False, f"a light figure on a dark background (its border is dark: {_percent(1 - light)} of it)"
    return False, (f"a light figure on a dark background, a guess: its border is split ({_percent(light)} light), "
                   "so the paper's convention")


def _open(im: Image.Image, size: int) -> tuple[Image.Image, int]:
    """An opened image, loaded, upright, in mode L, RGB, RGBA, I or F, and the factor to reduce it by for ``size``."""
    side = max(READ_SIDE, 2 * size)
    scale = side / max(im.size)
    if scale < 1:
        im.draft(im.mode, (math.ceil(im.size[0] * scale), math.ceil(im.size[1] * scale)))  # JPEG: decoded smaller
    im.load()
    ImageOps.exif_transpose(im, in_place=True)  # a phone's photo of a drawing, as its viewer shows it
    if im.mode in ("RGBa", "LA", "La", "PA") or (im.mode != "RGBA" and "transparency" in im.info):
        im = im.convert("RGBA")
    elif im.mode in _WIDE_MODES:
        im = im.convert("I")
    elif im.mode not in ("L", "RGB", "RGBA", "I", "F"):
        im = im.convert("L")
    return im, math.ceil(max(im.size) / side)


def _read_image(path: Path, size: int) -> tuple[np.ndarray, str]:
    """An image file's gray levels (float64, any range) and what they are: ``"gray"``, or ``"alpha"`` (its alpha channel)."""
    if not path.is_file():
        raise IFSError(f"no image file at {str(path)!r}")
    try:
        with Image.open(path) as opened:
            im, factor = _open(opened, size)

            def reduced(image: Image.Image) -> Image.Image:
                return image.reduce(factor) if factor > 1 else image

            if im.mode == "RGBA":
                # one channel at a time: reducing RGBA itself makes a premultiplied copy of the whole image
                alpha = np.asarray(reduced(im.getchannel("A")), dtype=np.float64) / 255
                if alpha.min() == alpha.max():
                    return np.asarray(reduced(im.convert("L")), dtype=np.float64) / 255, "gray"
                if (alpha[border_band(alpha.shape)] >= 0.5).mean() <= 0.5 + SPLIT:
                    return alpha, "alpha"
                # opaque at the border: the transparency is a hole or a corner, not the background
                im = reduced(im)
                white = Image.new("RGBA", im.size, (255, 255, 255, 255))
                return np.asarray(Image.alpha_composite(white, im).convert("L"), dtype=np.float64) / 255, "gray"
            im = reduced(im)
            if im.mode in ("I", "F"):
                return np.asarray(im, dtype=np.float64), "gray"
            return np.asarray(im.convert("L") if im.mode != "L" else im, dtype=np.float64) / 255, "gray"
    except Image.DecompressionBombError as exc:
        raise IFSError(f"{str(path)!r} is too large to read safely ({exc}); shrink it first") from None
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise IFSError(f"{str(path)!r} is not an image this library can read (PNG, GIF, JPEG): {exc}") from None


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
    gray = _scaled(gray)
    if invert:
        gray = 1 - gray
    if gray.shape != (size, size):
        gray = np.asarray(Image.fromarray(gray.astype(np.float32), mode="F").resize((size, size), Image.BILINEAR))
    return gray


def threshold_gray(gray: np.ndarray, threshold: float | None = None) -> np.ndarray:
    """The figure mask of a `resample_gray` image: at least ``threshold`` (0.5) of its largest value."""
    t = _check_threshold(threshold)
    return gray >= t * gray.max() if gray.max() > 0 else gray > 0


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


def _file_polarity(gray: np.ndarray, kind: str, invert: bool | None, threshold: float | None) -> tuple[bool, str]:
    """``(invert, polarity)`` of an image file's gray levels: as asked, or by `border_polarity`."""
    light, dark = ("opaque", "transparent") if kind == "alpha" else ("light", "dark")
    if invert is not None:
        return invert, f"the {dark if invert else light} part, as asked (invert={invert})"
    if kind == "alpha":
        return False, "an opaque figure on a transparent background (its alpha channel)"
    return border_polarity(gray, threshold)


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
        (module docstring); an array's figure is where it is high, an IFS's is its drawing.
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
    _check_threshold(threshold)
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
        gray, kind = _read_image(path, size)
        invert, polarity = _file_polarity(gray, kind, invert, threshold)
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
    return target_from_mask(threshold_gray(gray), target.name, gray, polarity=target.polarity, inverted=target.inverted)


def foreground_points(target: Target) -> np.ndarray:
    """Plane coordinates ``(k, 2)`` of the target's foreground pixel centres."""
    x, y = pixel_centres(target.size)
    flat = torch.from_numpy(target.mask.reshape(-1))
    return torch.stack([x[flat], y[flat]], 1).numpy()
