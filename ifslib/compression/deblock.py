"""The decoder's post-filter: each pair of pixels facing across a range block boundary replaced by a
weighted average of the two (Fisher, "Fractal Image Compression", 1995, ch. 3).

Blocks are coded apart, so their seams show as steps at low rates. With weight ``a`` (the file's
``deblock``), the pixels ``p | q`` either side of a boundary become ``(1 - a) p + a q`` and
``a p + (1 - a) q``: ``a = 0.5`` sets both to their mean. Columns are filtered, then rows. The filter is
linear and follows the blocks of either partition (squares or rectangles): it is a mask built once per
plan and two array operations, differentiable, so the attractor coder can fit what it outputs.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:  # decode imports this module
    from .decode import Plan


def boundaries(p: Plan) -> tuple[torch.Tensor, torch.Tensor]:
    """``(across columns (H, W - 1), across rows (H - 1, W))``: True between two pixels of different blocks."""
    label = torch.empty(p.height * p.width, dtype=torch.long)
    for g in p.groups:
        label[g.dst] = g.leaves[:, None]
    label = label.reshape(p.height, p.width)
    return label[:, 1:] != label[:, :-1], label[1:] != label[:-1]


def deblock(p: Plan, image: torch.Tensor, strength: float) -> torch.Tensor:
    """``image`` ``(H, W)`` (padded, at the plan's scale) with its block seams smoothed at weight ``strength``."""
    if strength == 0:
        return image
    cols, rows = boundaries(p)
    a = torch.as_tensor(strength, dtype=image.dtype)
    step = a * torch.where(cols, image[:, 1:] - image[:, :-1], 0)
    image = image + torch.nn.functional.pad(step, (0, 1)) - torch.nn.functional.pad(step, (1, 0))
    step = a * torch.where(rows, image[1:] - image[:-1], 0)
    return image + torch.nn.functional.pad(step, (0, 0, 0, 1)) - torch.nn.functional.pad(step, (0, 0, 1, 0))
