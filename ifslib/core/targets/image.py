"""Which part of an image file is the figure (the background touches the border: docs/guide/conventions.md,
"Targets and polarity"), and its gray levels on the target's grid."""
from __future__ import annotations

import math
from contextlib import contextmanager
from pathlib import Path

import numpy as np
from PIL import Image, ImageOps, UnidentifiedImageError

from ...errors import IFSError

#: Half-width of the band around an even split in which a border has no majority (`border_polarity`).
SPLIT = 0.1

#: The border band's width as a fraction of the image's smaller side (at least one pixel).
BORDER_BAND = 1 / 32

#: Pixels a side above which an image is reduced as it is read (never below twice the target's size).
READ_SIDE = 2048

# 16-bit modes, whose values Pillow's conversion to 8 bits would clip: read as 32-bit integers instead.
_WIDE_MODES = ("I;16", "I;16L", "I;16B", "I;16N")


def check_threshold(threshold) -> float:
    t = 0.5 if threshold is None else float(threshold)
    if not 0 < t < 1:
        raise IFSError(f"threshold must lie strictly between 0 and 1, got {threshold!r}")
    return t


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
    """Which part of an image is the figure, read from its border (the background touches it): ``invert`` and why,
    in words; a split border gives the paper's convention."""
    light = float((_scaled(gray)[border_band(np.shape(gray))] >= check_threshold(threshold)).mean())
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


def _luma(im: Image.Image) -> np.ndarray:
    """An 8-bit image's gray levels from 0 to 255, ``(h, w)`` float64 (colour by Pillow's luma)."""
    return np.asarray(im.convert("L") if im.mode != "L" else im, dtype=np.float64)


@contextmanager
def _image_file(path: Path):
    """The image at ``path``, opened; a missing, unreadable or too large file is an `IFSError` saying which."""
    if not path.is_file():
        raise IFSError(f"no image file at {str(path)!r}")
    try:
        with Image.open(path) as opened:
            yield opened
    except Image.DecompressionBombError as exc:
        raise IFSError(f"{str(path)!r} is too large to read safely ({exc}); shrink it first") from None
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise IFSError(f"{str(path)!r} is not an image this library can read (PNG, GIF, JPEG): {exc}") from None


def read_image(path: Path, size: int) -> tuple[np.ndarray, str]:
    """An image file's gray levels (float64, any range) and what they are: ``"gray"``, or ``"alpha"`` (its alpha channel)."""
    with _image_file(path) as opened:
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
        return _luma(im) / 255, "gray"


def resample_gray(gray: np.ndarray, size: int, invert: bool = False) -> np.ndarray:
    """A gray image scaled to ``[0, 1]`` by its own range, figure bright (``invert`` for a dark figure), resampled
    bilinearly to ``size x size``."""
    gray = _scaled(gray)
    if invert:
        gray = 1 - gray
    if gray.shape != (size, size):
        gray = np.asarray(Image.fromarray(gray.astype(np.float32), mode="F").resize((size, size), Image.BILINEAR))
    return gray


def threshold_gray(gray: np.ndarray, threshold: float | None = None) -> np.ndarray:
    """The figure mask of a `resample_gray` image: at least ``threshold`` (0.5) of its largest value."""
    t = check_threshold(threshold)
    return gray >= t * gray.max() if gray.max() > 0 else gray > 0


def file_polarity(gray: np.ndarray, kind: str, invert: bool | None, threshold: float | None) -> tuple[bool, str]:
    """``(invert, polarity)`` of an image file's gray levels: as asked, or by `border_polarity`."""
    light, dark = ("opaque", "transparent") if kind == "alpha" else ("light", "dark")
    if invert is not None:
        return invert, f"the {dark if invert else light} part, as asked (invert={invert})"
    if kind == "alpha":
        return False, "an opaque figure on a transparent background (its alpha channel)"
    return border_polarity(gray, threshold)
