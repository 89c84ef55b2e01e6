"""Losses between a rendered IFS and a target: pixel or distance, fine or multiscale; each name of
`ifslib.names.LOSSES` an entry of `LOSS_KINDS`."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import torch
import torch.nn.functional as F

from ...errors import IFSError
from ...names import DEFAULT_LOSS, LOSSES  # the names live apart, for the command line to check without torch
from ..raster.render import default_sigma, shade
from ..targets.target import Target


def _pixel_images(distance: torch.Tensor, target: Target, sigma: float | None) -> tuple[torch.Tensor, torch.Tensor]:
    """The rendered pixels ``exp(-relu(d)^2 / sigma^2)`` and the target's mask."""
    drawn = shade(distance, sigma or default_sigma(distance.shape[-1]))
    return drawn, target.image.to(drawn.device, drawn.dtype)


def _distance_images(distance: torch.Tensor, target: Target, sigma: float | None) -> tuple[torch.Tensor, torch.Tensor]:
    """``relu(d)`` and the target's distance transform (plane units)."""
    drawn = torch.relu(distance)
    return drawn, target.distance.to(drawn.device, drawn.dtype)


@dataclass(frozen=True)
class Family:
    """What a family of losses compares: its ``images(distance, target, sigma) -> (drawn, wanted)``, how `pyramid`
    pools them (``"avg"`` a mask, ``"min"`` a distance), and what the ``anneal`` strategy ``sharpens``."""

    images: Callable[[torch.Tensor, Target, float | None], tuple[torch.Tensor, torch.Tensor]]
    pool: str
    sharpens: str


PIXEL = Family(_pixel_images, "avg", "sigma")
DISTANCE = Family(_distance_images, "min", "levels")


def mse(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """Mean squared error of two images ``(h, w)`` (a scalar), or per image of a batch ``(B, h, w)`` (``(B,)``)."""
    # row means first: one reduction of a whole image is split between threads (its last bits follow their count)
    return (a - b).square().mean(-1).mean(-1)


@dataclass(frozen=True)
class LossKind:
    """A named loss: its family, whether it is summed over the images' pyramids (the paper's multiscale MSE), and how
    two of its images are compared (``compare(drawn, wanted)``: a scalar, or ``(B,)`` for a batch)."""

    family: Family
    multiscale: bool
    compare: Callable[[torch.Tensor, torch.Tensor], torch.Tensor] = mse


#: Every loss of `ifslib.names.LOSSES` (a test says the two agree).
LOSS_KINDS = {
    "pixel": LossKind(PIXEL, multiscale=False),
    "multiscale_pixel": LossKind(PIXEL, multiscale=True),
    "distance": LossKind(DISTANCE, multiscale=False),
    "multiscale_distance": LossKind(DISTANCE, multiscale=True),
}


def check_loss(kind) -> str | Callable:
    """Return ``kind`` if it is a callable or one of `LOSSES`, else raise `IFSError` naming them."""
    if not callable(kind) and kind not in LOSSES:
        raise IFSError(f"unknown loss {kind!r}; known losses: {', '.join(LOSSES)} (or a function f(distance, target))")
    return kind


def loss_kind(kind: str) -> LossKind:
    """The `LossKind` of a loss's name (`IFSError` for an unknown one)."""
    return LOSS_KINDS[check_loss(kind)]


def pyramid(image: torch.Tensor, levels: int, mode: str = "avg") -> list[torch.Tensor]:
    """The ``(h, w)`` (or ``(B, h, w)``) image and ``levels`` copies, each 2 x 2 pooled from the previous (down to 1 x 1)."""
    out = [image]
    lead = image.shape[:-2]
    x = image.reshape(-1, 1, *image.shape[-2:])
    for _ in range(levels):
        if min(x.shape[-2:]) <= 1:
            break
        x = F.avg_pool2d(x, 2, ceil_mode=True) if mode == "avg" else -F.max_pool2d(-x, 2, ceil_mode=True)
        out.append(x.reshape(*lead, *x.shape[-2:]))
    return out


def multiscale(compare: Callable[[torch.Tensor, torch.Tensor], torch.Tensor], a: torch.Tensor, b: torch.Tensor,
               levels: int = 5, mode: str = "avg") -> torch.Tensor:
    """``compare`` summed over the two images' pyramids (see `pyramid`)."""
    return sum(compare(x, y) for x, y in zip(pyramid(a, levels, mode), pyramid(b, levels, mode)))


def multiscale_mse(a: torch.Tensor, b: torch.Tensor, levels: int = 5, mode: str = "avg") -> torch.Tensor:
    """MSE summed over the two images' pyramids (see `pyramid`): the paper's multiscale loss."""
    return multiscale(mse, a, b, levels, mode)


def loss(distance: torch.Tensor, target: Target, kind: str | Callable = DEFAULT_LOSS,
         sigma: float | None = None, levels: int = 5) -> torch.Tensor:
    """The loss of a distance field (or a batch of them: one each) against a target: a name of `LOSSES` or
    ``f(distance, target)``; ``sigma`` for the pixel losses, ``levels`` for the multiscale ones."""
    if callable(kind):
        if distance.ndim == 3:
            return torch.stack([kind(d, target) for d in distance])
        return kind(distance, target)
    named = loss_kind(kind)
    if distance.shape[-2:] != target.mask.shape or distance.ndim not in (2, 3):
        raise IFSError(f"the distance field is {tuple(distance.shape)} but the target is {target.mask.shape}")
    a, b = named.family.images(distance, target, sigma)
    return multiscale(named.compare, a, b, levels, named.family.pool) if named.multiscale else named.compare(a, b)
