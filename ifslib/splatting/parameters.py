"""Affine maps in a parameterization that keeps every map contractive: ``A = R(theta) diag(s1, s2) R(phi)``.

Each map's linear part is written as a rotation, two singular values and a rotation. The first singular value is
``MAX_SCALE * sigmoid(a)`` and the second ``MAX_SCALE * tanh(b)`` (its sign is the map's reflection, so a map can
flip continuously through a flat map), so whatever the raw numbers Adam moves, every map's largest singular value
stays below `MAX_SCALE` < 1 and the attractor exists at every step. The translation is free.
"""
from __future__ import annotations

import math

import torch

from ..errors import IFSError
from .config import MAX_SCALE

#: Columns of the raw parameters: theta, phi, a (first singular value's logit), b (second's atanh), tx, ty.
WIDTH = 6


def _rotation(angle: torch.Tensor) -> torch.Tensor:
    """``(m,)`` angles to ``(m, 2, 2)`` rotations."""
    c, s = angle.cos(), angle.sin()
    return torch.stack([torch.stack([c, -s], -1), torch.stack([s, c], -1)], -2)


class ContractiveMaps:
    """``m`` trainable affine maps of scale below ``max_scale``.

    Attributes
    ----------
    raw : torch.Tensor
        ``(m, 6)`` leaf tensor with ``requires_grad``: theta, phi, a, b, tx, ty (`WIDTH` columns).
    max_scale : float
        The bound on every map's largest singular value, in (0, 1).
    """

    def __init__(self, raw: torch.Tensor, max_scale: float = MAX_SCALE) -> None:
        if not (isinstance(max_scale, float) and 0 < max_scale < 1):
            raise IFSError(f"max_scale must be a float in (0, 1), got {max_scale!r}")
        if raw.ndim != 2 or raw.shape[1] != WIDTH or raw.shape[0] < 1:
            raise IFSError(f"raw parameters must have shape (m, {WIDTH}) with m >= 1, got {tuple(raw.shape)}")
        if not torch.isfinite(raw).all():
            raise IFSError("raw parameters must be finite")
        self.raw = raw.detach().clone().requires_grad_(True)
        self.max_scale = max_scale

    @classmethod
    def from_maps(cls, maps, max_scale: float = MAX_SCALE, dtype: torch.dtype = torch.float32) -> "ContractiveMaps":
        """The parameters of given maps ``(m, 3, 3)`` or ``(m, 2, 3)``; a singular value at or above ``max_scale``
        is brought just below it (the parameterization cannot hold it), one of 0 just above it."""
        maps = torch.as_tensor(maps, dtype=torch.float64)
        if maps.ndim != 3 or maps.shape[1:] not in ((3, 3), (2, 3)) or maps.shape[0] < 1:
            raise IFSError(f"maps must have shape (m, 3, 3) or (m, 2, 3), got {tuple(maps.shape)}")
        if not torch.isfinite(maps).all():
            raise IFSError("maps must be finite")
        u, s, vh = torch.linalg.svd(maps[:, :2, :2])
        sign = torch.linalg.det(u).sign() * torch.linalg.det(vh).sign()  # -1: a reflection, carried by s2's sign
        u, vh = u @ torch.diag_embed(torch.stack([torch.ones_like(sign), torch.linalg.det(u).sign()], -1)), \
            torch.diag_embed(torch.stack([torch.ones_like(sign), torch.linalg.det(vh).sign()], -1)) @ vh
        top = 1 - 1e-4
        s1 = (s[:, 0] / max_scale).clamp(1e-4, top)
        s2 = (sign * s[:, 1] / max_scale).clamp(-top, top)
        raw = torch.stack([torch.atan2(u[:, 1, 0], u[:, 0, 0]), torch.atan2(vh[:, 1, 0], vh[:, 0, 0]),
                           torch.logit(s1), torch.atanh(s2), maps[:, 0, 2], maps[:, 1, 2]], 1)
        return cls(raw.to(dtype), max_scale)

    def __len__(self) -> int:
        return self.raw.shape[0]

    def linear(self) -> torch.Tensor:
        """``(m, 2, 2)`` linear parts, differentiable in `raw`."""
        theta, phi, a, b = self.raw[:, 0], self.raw[:, 1], self.raw[:, 2], self.raw[:, 3]
        scales = torch.stack([self.max_scale * torch.sigmoid(a), self.max_scale * torch.tanh(b)], -1)
        return _rotation(theta) @ torch.diag_embed(scales) @ _rotation(phi)

    def maps(self) -> torch.Tensor:
        """``(m, 3, 3)`` homogeneous maps ``[[A, t], [0, 0, 1]]``, differentiable in `raw`."""
        m = len(self)
        top = torch.cat([self.linear(), self.raw[:, 4:6, None]], 2)
        bottom = torch.zeros(m, 1, 3, dtype=self.raw.dtype, device=self.raw.device)
        bottom[..., 2] = 1
        return torch.cat([top, bottom], 1)

    def replace(self, index: int, maps_row) -> None:
        """Set map ``index`` to the ``(3, 3)`` (or ``(2, 3)``) map ``maps_row`` (a reselected map), in place."""
        new = ContractiveMaps.from_maps(torch.as_tensor(maps_row)[None], self.max_scale, self.raw.dtype).raw
        with torch.no_grad():
            self.raw[index] = new[0].to(self.raw.device)


def random_raw(m: int, scales: tuple[float, float], generator: torch.Generator, max_scale: float = MAX_SCALE,
               dtype: torch.dtype = torch.float32) -> torch.Tensor:
    """``(m, 6)`` raw parameters of random maps (uniform angles, singular values uniform in ``scales``, a reflection
    with chance 1/2), translations 0 (the caller places them)."""
    lo, hi = scales
    if not 0 < lo <= hi < max_scale:
        raise IFSError(f"start scales must satisfy 0 < low <= high < {max_scale}, got {scales!r}")
    u = torch.rand(m, 5, generator=generator, dtype=torch.float64)
    s1 = lo + (hi - lo) * torch.maximum(u[:, 2], u[:, 3])
    s2 = (lo + (hi - lo) * torch.minimum(u[:, 2], u[:, 3])) * torch.where(u[:, 4] < 0.5, -1.0, 1.0)
    raw = torch.stack([2 * math.pi * u[:, 0], 2 * math.pi * u[:, 1], torch.logit(s1 / max_scale),
                       torch.atanh(s2 / max_scale), torch.zeros(m, dtype=torch.float64),
                       torch.zeros(m, dtype=torch.float64)], 1)
    return raw.to(dtype)
