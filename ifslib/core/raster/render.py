"""`render`: distances to pixel intensities, ``exp(-relu(d)^2 / sigma^2)`` in ``[0, 1]``, ``sigma`` one pixel
by default (a thin curve renders about two pixels wide at any resolution)."""
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
    """Render an IFS to a ``(size, size)`` image in ``[0, 1]``, differentiable (``**kwargs``: `distance_field`'s);
    ``method="chaos"`` draws the attractor from chaos-game points, without gradient."""
    if window is not None:
        window = check_window(window)
    sigma = _sigma(ifs, size, sigma, window)
    if method == "chaos":
        if depth not in (None, "attractor"):
            raise IFSError(f"the chaos game draws the attractor: depth {depth!r} does not apply")
        return shade(chaos_field(ifs, size, points, seed, window), sigma)
    return shade(distance_field(ifs, size, depth, method, window=window, **kwargs), sigma)


def figure_mask(ifs: IFS, size: int, depth: int | str | None = None, sigma: float | None = None, **kwargs):
    """The fractal's pixels: where its `render` (``**kwargs``) is >= 0.5, a ``(size, size)`` bool array. The chaos
    game's mask is read from the points near each pixel (`_chaos_mask`): the same pixels in half the time."""
    if kwargs.get("method") == "chaos" and kwargs.get("window") is None and depth in (None, "attractor"):
        return _chaos_mask(ifs, size, sigma, kwargs.get("points", DEFAULT_POINTS), kwargs.get("seed", 0))
    with torch.no_grad():
        return render(ifs, size, depth, sigma, **kwargs).cpu().numpy() >= 0.5


#: Past ``sigma`` times this (``sqrt(ln 2) = 0.83256``, with room for rounding) a shade is below 0.5.
_HALF_SHADE = 0.8326


def _chaos_mask(ifs: IFS, size: int, sigma: float | None, points: int, seed: int):
    """`figure_mask` of the chaos game's drawing from the pairs of pixels and points within ``sigma * sqrt(ln 2)``
    (`chaos_reach`), the only ones whose shade can reach 0.5."""
    size = check_size(size)
    sigma = check_sigma(_sigma(ifs, size, sigma))
    pixel, distance = chaos_reach(ifs, size, sigma * _HALF_SHADE, points, seed)
    mask = np.zeros(size * size, bool)
    mask[pixel[shade(torch.from_numpy(distance), sigma).numpy() >= 0.5]] = True
    return mask.reshape(size, size)
