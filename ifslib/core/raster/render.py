"""`render`: distances to pixel intensities, ``exp(-relu(d)^2 / sigma^2)`` in ``[0, 1]``.

The default ``sigma`` is one pixel, ``1 / size`` in plane units: a pixel whose centre lies one
pixel from the figure gets ``exp(-1) ~ 0.37``, so a thin curve renders about two pixels wide at any
resolution. Pixels inside a closed shape (negative distance) are 1.
"""
from __future__ import annotations

import numpy as np
import torch

from ...errors import IFSError
from ..geometry.attractor import check_window
from ..geometry.ifs import IFS, check_sigma
from .chaos import DEFAULT_POINTS, chaos_field, chaos_reach
from .distance import check_size, distance_field, pixel_size


def default_sigma(size: int) -> float:
    """The default rendering width: one pixel, ``1 / size`` plane units."""
    return 1.0 / check_size(size)


def shade(distance: torch.Tensor, sigma: float) -> torch.Tensor:
    """Pixel intensities from signed distances: ``exp(-relu(d)^2 / sigma^2)``, same shape."""
    return torch.exp(-torch.relu(distance).square() / check_sigma(sigma) ** 2)


def _sigma(ifs: IFS, size: int, sigma: float | None, window=None) -> float:
    """The rendering width: ``sigma`` when given, else the IFS's own, else one pixel (of the window, when given)."""
    if sigma is not None:
        return sigma
    return ifs.sigma if ifs.sigma is not None else pixel_size(size, window)


def render(ifs: IFS, size: int, depth: int | str | None = None, sigma: float | None = None, *,
           method: str = "fast", window=None, points: int = DEFAULT_POINTS, seed: int = 0, **kwargs) -> torch.Tensor:
    """Render an IFS to a ``(size, size)`` image in ``[0, 1]``, 1 on the figure.

    Parameters
    ----------
    ifs : IFS
    size : int
        Pixels per side.
    depth : int or "attractor", optional
        ``ifs.depth`` when None; ``"attractor"`` draws the attractor itself (see
        `ifslib.distance_field`), as does a ``window``.
    sigma : float, optional
        Width in plane units; ``ifs.sigma`` when set, else one pixel (of the window, when given).
    method : {"fast", "brute", "chaos"}
        ``"chaos"`` draws the attractor from ``points`` chaos-game points (`ifslib.chaos_game`,
        seeded by ``seed``): the classic picture, float64, with no gradient.
    window : (x0, y0, x1, y1), optional
        The box of the plane to draw (the frame ``[-0.5, 0.5]^2`` when None), at full detail: the
        attractor's leaves are refined for this window's pixels.
    points, seed
        For ``method="chaos"``.
    **kwargs
        Passed to `ifslib.distance_field` (``device``, ``dtype``, ``gradient``, ``tolerance``, ...).

    Returns
    -------
    torch.Tensor
        ``(size, size)``, differentiable in ``ifs.points`` (except with ``method="chaos"``).
    """
    if window is not None:
        window = check_window(window)
    sigma = _sigma(ifs, size, sigma, window)
    if method == "chaos":
        if depth not in (None, "attractor"):
            raise IFSError(f"the chaos game draws the attractor: depth {depth!r} does not apply")
        return shade(chaos_field(ifs, size, points, seed, window), sigma)
    return shade(distance_field(ifs, size, depth, method, window=window, **kwargs), sigma)


def figure_mask(ifs: IFS, size: int, depth: int | str | None = None, sigma: float | None = None, **kwargs):
    """The fractal's pixels: where its render is >= 0.5, as a ``(size, size)`` bool numpy array.

    ``depth="attractor"`` gives the attractor's pixels; ``**kwargs`` go to `render`. The chaos game's mask
    (``method="chaos"`` without a window) is read from the points near each pixel instead of a distance field
    of every pixel: the same pixels, in about half the time.
    """
    if kwargs.get("method") == "chaos" and kwargs.get("window") is None and depth in (None, "attractor"):
        return _chaos_mask(ifs, size, sigma, kwargs.get("points", DEFAULT_POINTS), kwargs.get("seed", 0))
    with torch.no_grad():
        return render(ifs, size, depth, sigma, **kwargs).cpu().numpy() >= 0.5


#: Past ``sigma`` times this (``sqrt(ln 2) = 0.83256``, with room for rounding) a shade is below 0.5.
_HALF_SHADE = 0.8326


def _chaos_mask(ifs: IFS, size: int, sigma: float | None, points: int, seed: int):
    """`figure_mask` of the chaos game's drawing, from the pairs of pixels and points within ``0.8326 sigma``
    (`chaos_reach`): a pixel's shade is at least 0.5 only within ``sigma * sqrt(ln 2)`` of a point, and shading
    each pair as `render` shades the nearest point's distance gives the same pixels, without a KD-tree."""
    size = check_size(size)
    sigma = check_sigma(_sigma(ifs, size, sigma))
    pixel, distance = chaos_reach(ifs, size, sigma * _HALF_SHADE, points, seed)
    mask = np.zeros(size * size, bool)
    mask[pixel[shade(torch.from_numpy(distance), sigma).numpy() >= 0.5]] = True
    return mask.reshape(size, size)
