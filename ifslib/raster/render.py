"""`render`: distances to pixel intensities, ``exp(-relu(d)^2 / sigma^2)`` in ``[0, 1]``.

The default ``sigma`` is one pixel, ``1 / size`` in plane units: a pixel whose centre lies one
pixel from the figure gets ``exp(-1) ~ 0.37``, so a thin curve renders about two pixels wide at any
resolution. Pixels inside a closed shape (negative distance) are 1.
"""
from __future__ import annotations

import torch

from .distance import check_size, distance_field
from ..geometry.ifs import IFS, check_sigma


def default_sigma(size: int) -> float:
    """The default rendering width: one pixel, ``1 / size`` plane units."""
    return 1.0 / check_size(size)


def shade(distance: torch.Tensor, sigma: float) -> torch.Tensor:
    """Pixel intensities from signed distances: ``exp(-relu(d)^2 / sigma^2)``, same shape."""
    return torch.exp(-torch.relu(distance).square() / check_sigma(sigma) ** 2)


def render(ifs: IFS, size: int, depth: int | None = None, sigma: float | None = None, **kwargs) -> torch.Tensor:
    """Render an IFS to a ``(size, size)`` image in ``[0, 1]``, 1 on the figure.

    Parameters
    ----------
    ifs : IFS
    size : int
        Pixels per side.
    depth : int, optional
        ``ifs.depth`` when None.
    sigma : float, optional
        Width in plane units; ``ifs.sigma`` when set, else `default_sigma` (one pixel).
    **kwargs
        Passed to `ifslib.distance_field` (``method``, ``device``, ``dtype``, ``gradient``, ...).

    Returns
    -------
    torch.Tensor
        ``(size, size)``, differentiable in ``ifs.points``.
    """
    if sigma is None:
        sigma = ifs.sigma if ifs.sigma is not None else default_sigma(size)
    return shade(distance_field(ifs, size, depth, **kwargs), sigma)


def figure_mask(ifs: IFS, size: int, depth: int | None = None, sigma: float | None = None):
    """The fractal's pixels: where its render is >= 0.5, as a ``(size, size)`` bool numpy array."""
    with torch.no_grad():
        return render(ifs, size, depth, sigma).cpu().numpy() >= 0.5
