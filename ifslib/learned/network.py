"""The network: a convolutional encoder-decoder that reads the target's picture and, on a grid of slots over the
frame, says for each slot whether a map's copy is centred there and which map it is (six numbers). The set loss
matches true maps to slots (`set_loss`); a slot's anchor, its cell's centre, gives the convolutions where to look,
so the matching settles from the first step (the literature's set predictor, Yamaguti 2025-26, with anchors)."""
from __future__ import annotations

import torch
import torch.nn.functional as F
from torch import nn

from . import config


def _block(inputs: int, outputs: int, stride: int = 1) -> nn.Sequential:
    """Two 3x3 convolutions, group-normalized (a batch of one at run time), the first with ``stride``."""
    return nn.Sequential(nn.Conv2d(inputs, outputs, 3, stride=stride, padding=1), nn.GroupNorm(8, outputs), nn.ReLU(),
                         nn.Conv2d(outputs, outputs, 3, padding=1), nn.GroupNorm(8, outputs), nn.ReLU())


class GuessNet(nn.Module):
    """``(B, 1, SIZE, SIZE)`` pictures -> ``(B, GRID², 2, 3)`` maps and ``(B, GRID²)`` presence logits, a slot a cell
    of the ``GRID x GRID`` grid over the frame, row-major from the top left.

    The picture is read beside two channels of its pixels' plane coordinates (CoordConv). A slot's map is its
    linear part and its shift, the shift an offset (in cells) from the slot's anchor: a map's shift is where it
    sends the attractor's centre, the centre of its copy.
    """

    def __init__(self, size: int = config.SIZE, grid: int = config.GRID, width: int = config.WIDTH) -> None:
        super().__init__()
        if size % 16 or size // grid != 4:
            raise ValueError(f"the network reads pictures of 4 x grid pixels a side, a multiple of 16: got {size}, {grid}")
        self.size, self.grid = size, grid
        w = width
        self.down = nn.ModuleList([_block(3, w, 2), _block(w, 2 * w, 2), _block(2 * w, 4 * w, 2), _block(4 * w, 8 * w, 2)])
        self.up = nn.ModuleList([_block(12 * w, 4 * w), _block(6 * w, 2 * w)])
        self.out = nn.Conv2d(2 * w, 7, 1)
        t = (torch.arange(size) + 0.5) / size
        self.register_buffer("coords", torch.stack(torch.meshgrid(0.5 - t, t - 0.5, indexing="ij")[::-1]),
                             persistent=False)
        c = (torch.arange(grid) + 0.5) / grid
        y, x = torch.meshgrid(0.5 - c, c - 0.5, indexing="ij")
        self.register_buffer("anchors", torch.stack([x, y], -1).reshape(-1, 2), persistent=False)

    @property
    def slots(self) -> int:
        return self.grid ** 2

    def forward(self, pictures: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        x = torch.cat([pictures, self.coords.expand(len(pictures), -1, -1, -1)], 1)
        skips = []
        for stage in self.down:
            x = stage(x)
            skips.append(x)
        for stage, skip in zip(self.up, (skips[2], skips[1])):
            x = stage(torch.cat([F.interpolate(x, scale_factor=2.0), skip], 1))
        out = self.out(x).flatten(2).transpose(1, 2)                     # (B, GRID², 7)
        shifts = self.anchors + out[:, :, 4:6] / self.grid
        maps = torch.cat([out[:, :, :4].reshape(-1, self.slots, 2, 2), shifts[:, :, :, None]], 3)
        return maps, out[:, :, 6]
