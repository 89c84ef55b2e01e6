"""`render`: distances to pixel intensities, ``exp(-relu(d)^2 / sigma^2)`` in ``[0, 1]``.

The default ``sigma`` is one pixel, ``1 / size`` in plane units: a pixel whose centre lies one
pixel from the figure gets ``exp(-1) ~ 0.37``, so a thin curve renders about two pixels wide at any
resolution. Pixels inside a closed shape (negative distance) are 1.
"""
from __future__ import annotations

import math

import torch

from .distance import check_size, distance_field
from .errors import IFSError
from .ifs import IFS


def default_sigma(size: int) -> float:
    """The default rendering width: one pixel, ``1 / size`` plane units."""
    return 1.0 / check_size(size)


def check_sigma(sigma) -> float:
    """Return ``sigma`` as a float if it is finite and > 0, else raise `IFSError`."""
    try:
        value = float(sigma)
    except (TypeError, ValueError):
        raise IFSError(f"sigma must be a number > 0, got {sigma!r}") from None
    if not (value > 0 and math.isfinite(value)):
        raise IFSError(f"sigma must be a finite number > 0, got {sigma!r}")
    return value


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
