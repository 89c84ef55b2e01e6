"""The two coders by name: ``collage`` (the classic) and ``attractor`` (the collage code refined through the decoder)."""
from __future__ import annotations

from ..errors import IFSError
from .code import Code
from .config import CodeOptions, RefineOptions
from .encode import budget, collage
from .refine import refine

from ..names import COMPRESSION_METHODS as METHODS  # noqa: E402 - the names live apart, for the command line


def compress(image, bpp: float | None = None, quality: float | None = None, method: str = "attractor",
             options: CodeOptions = CodeOptions(), refinement: RefineOptions = RefineOptions(),
             progress: bool = False) -> Code:
    """The code of a gray image by one of `METHODS`, at a rate or a collage quality.

    Parameters
    ----------
    image : array or torch.Tensor
        ``(h, w)`` gray levels in [0, 1].
    bpp, quality : float, optional
        Exactly one: the file's bits per pixel, or the collage's PSNR in dB (`encode.encode`).
    method : str
        ``"collage"`` or ``"attractor"`` (no more bits, a closer decoded image).
    options, refinement : CodeOptions, RefineOptions
    progress : bool

    Returns
    -------
    Code
    """
    if method not in METHODS:
        raise IFSError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    chosen = collage(image, options, bpp=bpp, quality=quality, progress=progress)
    if method == "collage":
        return chosen.code
    rate = None if bpp is None else budget(bpp, None, chosen.code.height, chosen.code.width, options)[0]
    return refine(chosen.code, image, refinement, progress, chosen, rate)
