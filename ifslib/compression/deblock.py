"""The decoder's post-filter: each pair of pixels facing across a range block boundary replaced by a
weighted average of the two (Fisher, "Fractal Image Compression", 1995, ch. 3).

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import torch


def boundaries(labels: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """``(across columns (H, W - 1), across rows (H - 1, W))``: True between two pixels of different blocks, for
    ``labels`` ``(H, W)``, each pixel's block."""
    return labels[:, 1:] != labels[:, :-1], labels[1:] != labels[:-1]


def deblock(labels: torch.Tensor, image: torch.Tensor, strength: float) -> torch.Tensor:
    """``image`` ``(H, W)`` with the seams between the blocks of ``labels`` ``(H, W)`` smoothed at weight ``strength``."""
    if strength == 0:
        return image
    cols, rows = boundaries(labels)
    a = torch.as_tensor(strength, dtype=image.dtype)
    step = a * torch.where(cols, image[:, 1:] - image[:, :-1], 0)
    image = image + torch.nn.functional.pad(step, (0, 1)) - torch.nn.functional.pad(step, (1, 0))
    step = a * torch.where(rows, image[1:] - image[:-1], 0)
    return image + torch.nn.functional.pad(step, (0, 0, 0, 1)) - torch.nn.functional.pad(step, (0, 0, 1, 0))
