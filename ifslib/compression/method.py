"""The two coders by name: ``collage`` (the classic) and ``attractor`` (the collage code refined through the decoder)."""
from __future__ import annotations

from dataclasses import replace

import torch

from ..errors import IFSError
from .code import Code
from .config import DEBLOCK, CodeOptions, RefineOptions
from .encode import budget, check_image, collage
from .refine import decoded_error, refine

from ..names import COMPRESSION_METHODS as METHODS  # noqa: E402 - the names live apart, for the command line


def compress(image, bpp: float | None = None, quality: float | None = None, method: str = "attractor",
             options: CodeOptions = CodeOptions(), refinement: RefineOptions = RefineOptions(),
             progress: bool = False, deblock: float | None = None) -> Code:
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
    deblock : float, optional
        The decoder's post-filter weight to try (default `config.DEBLOCK`; 0: none; with
        ``coder="fixed"`` none, version 1 cannot record it; ``options.deblock``, if set, is used as
        given): the code is fitted for the filtered decoding, then the filter kept only if the file
        decodes closer with it than without.

    Returns
    -------
    Code
    """
    if method not in METHODS:
        raise IFSError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if options.deblock or options.coder == "fixed":
        return _compress(image, bpp, quality, method, options, refinement, progress)
    strength = DEBLOCK if deblock is None else deblock
    # the filter's byte lengthens the header, so the fields get a byte less: _compress codes for the filter
    code = _compress(image, bpp, quality, method, replace(options, deblock=strength), refinement, progress)
    if strength:
        target = check_image(image).to(torch.float32)
        off = replace(code, options=replace(code.options, deblock=0.0))
        if decoded_error(off, target)[0] <= decoded_error(code, target)[0]:
            return off
    return code


def _compress(image, bpp, quality, method, options, refinement, progress) -> Code:
    chosen = collage(image, options, bpp=bpp, quality=quality, progress=progress)
    if method == "collage":
        return chosen.code
    rate = None if bpp is None else budget(bpp, None, chosen.code.height, chosen.code.width, options)[0]
    return refine(chosen.code, image, refinement, progress, chosen, rate)
