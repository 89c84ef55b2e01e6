"""How far a window's pixels can be from the attractor: per-block upper bounds that prune the word tree
(docs/results/attractor.md, step 4)."""
from __future__ import annotations

import functools
import math

import torch

#: Blocks per side of the window.
GRID = 32

#: A level of fewer nodes leaves the blocks' bounds as they are (any bound found earlier still holds):
#: spreading them costs more than pruning so few nodes saves.
FEW = 1 << 12

#: At most this many nodes of a level tighten the bounds (every ``N // SAMPLES``-th).
SAMPLES = 1 << 14


def to_window(points: torch.Tensor, window: tuple[float, float, float, float]) -> torch.Tensor:
    """Distance from each of ``(N, 2)`` points to the box ``window`` (0 inside): ``(N,)``."""
    x0, y0, x1, y1 = window
    dx = torch.clamp(torch.maximum(x0 - points[:, 0], points[:, 0] - x1), min=0)
    dy = torch.clamp(torch.maximum(y0 - points[:, 1], points[:, 1] - y1), min=0)
    return torch.hypot(dx, dy)


def _box_gap(lo_a: torch.Tensor, hi_a: torch.Tensor, lo_b: torch.Tensor, hi_b: torch.Tensor) -> torch.Tensor:
    """Distance between boxes ``(N, 2)`` corners ``a`` and ``(M, 2)`` corners ``b`` (points: lo = hi): ``(N, M)``."""
    gap = torch.clamp(torch.maximum(lo_b[None] - hi_a[:, None], lo_a[:, None] - hi_b[None]), min=0)
    return torch.hypot(gap[..., 0], gap[..., 1])


def _boxes(window: tuple[float, float, float, float], n: int, shift: int, dtype: torch.dtype,
           device: torch.device) -> tuple[torch.Tensor, torch.Tensor]:
    """Corners ``(n * n, 2)`` of an ``n x n`` grid of block-sized cells, ``shift`` cells left of and below
    the window."""
    x0, y0, x1, y1 = window
    step = torch.tensor([(x1 - x0) / GRID, (y1 - y0) / GRID], dtype=torch.float64)
    k = torch.arange(n, dtype=torch.float64) - shift
    col, row = k.repeat(n), k.repeat_interleave(n)  # id = row * n + col
    corner = torch.stack([x0 + col * step[0], y0 + row * step[1]], 1)
    return corner.to(device, dtype), (corner + step).to(device, dtype)


@functools.lru_cache(maxsize=8)
def _tables(window: tuple[float, float, float, float], dtype: torch.dtype, device: torch.device):
    """A window's blocks and the gaps between them, cached: a fit asks for one a step, and the gaps (a million box
    pairs) cost more than the step's pruning. Nothing here is changed in place."""
    lo, hi = _boxes(window, GRID, 0, dtype, device)
    x0, y0, x1, y1 = window
    k = torch.arange(GRID, dtype=dtype, device=device)
    hop = [(k[:, None] - k[None]).abs() * step for step in ((x1 - x0) / GRID, (y1 - y0) / GRID)]  # (GRID, GRID) per axis
    col, row = torch.arange(GRID).repeat(GRID), torch.arange(GRID).repeat_interleave(GRID)
    border = ((col == 0) | (col == GRID - 1) | (row == 0) | (row == GRID - 1)).nonzero().flatten().to(device)
    gap = _box_gap(lo[border], hi[border], lo, hi)  # (border, B)
    # the cells around the window, a window's width on each side, and their gaps to the border blocks
    cell_lo, cell_hi = _boxes(window, 3 * GRID, GRID, dtype, device)
    cell_gap = _box_gap(cell_lo, cell_hi, lo[border], hi[border])  # (cells, border)
    return lo, hi, hop, gap, cell_gap


class WindowReach:
    """Per-block upper bounds ``U_b`` of ``d(x, A)`` over a window, and the pruning test they give.

    Also keeps the coarser bound of the whole window, ``U = min_w (|m - p_w| + e_w) + h`` (``m`` its
    centre, ``h`` its half-diagonal; `ifslib.core.geometry.attractor`, step 4).

    Parameters
    ----------
    window : (x0, y0, x1, y1)
        Checked by the caller.
    margin : float
        How far outside its node's ball a leaf of the node can lie, plus how much farther than the
        nearest point of the attractor a pixel's nearest leaf can be: twice the tolerance.
    dtype, device
        Those of the nodes' points.
    """

    def __init__(self, window: tuple[float, float, float, float], margin: float, dtype: torch.dtype,
                 device: torch.device) -> None:
        x0, y0, x1, y1 = window
        self.window, self.step, self.margin = window, ((x1 - x0) / GRID, (y1 - y0) / GRID), margin
        self.mid = torch.tensor([(x0 + x1) / 2, (y0 + y1) / 2], dtype=dtype, device=device)
        self.half, self.whole = math.hypot(x1 - x0, y1 - y0) / 2, math.inf
        self.lo, self.hi, self.hop, self.gap, self.cell_gap = _tables(tuple(map(float, window)), dtype, device)
        self.upper = torch.full((GRID * GRID,), math.inf, dtype=dtype, device=device)
        self._spread()

    def _cell(self, points: torch.Tensor, n: int, shift: int) -> tuple[torch.Tensor, torch.Tensor]:
        """Each point's cell id in the ``n x n`` grid of `_boxes` (clamped to it), and whether it lies in the grid."""
        col = ((points[:, 0] - self.window[0]) / self.step[0]).floor() + shift
        row = ((points[:, 1] - self.window[1]) / self.step[1]).floor() + shift
        inside = (col >= 0) & (col < n) & (row >= 0) & (row < n)
        return (row.clamp(0, n - 1) * n + col.clamp(0, n - 1)).long(), inside

    def _spread(self) -> None:
        # along rows, then along columns: U_b <= U_b' + |dx| + |dy|, no tighter than the straight line but
        # valid, in 2 GRID^3 steps rather than GRID^4
        grid = self.upper.view(GRID, GRID)  # (row, col)
        grid = (grid[:, :, None] + self.hop[0][None]).amin(1)
        grid = (grid[:, None, :] + self.hop[1][:, :, None]).amin(0)
        self.upper = grid.reshape(-1)
        reach = (self.upper[None] - self.gap).amax(1)  # V of the border blocks
        self.widest = float(reach.max())
        self.need = (self.cell_gap - reach[None]).amin(1)  # a lower bound of min_b' d(p, b') - V_b' over each cell

    def update(self, points: torch.Tensor, error: torch.Tensor) -> None:
        """Tighten the bounds with nodes ``(N, 2)`` points and ``(N,)`` errors (their balls hold attractor points)."""
        self.whole = min(self.whole, float(((points - self.mid).norm(dim=1) + error).min()) + self.half)
        if points.shape[0] < FEW:
            return
        # any subset of the nodes gives valid bounds; a few per block are as tight as all of them
        stride = -(-points.shape[0] // SAMPLES)
        points, error = points[::stride], error[::stride]
        block = self._cell(points, GRID, 0)[0]
        lo, hi = self.lo[block], self.hi[block]
        far = torch.maximum((points - lo).abs(), (points - hi).abs())  # the block's farthest corner, per axis
        self.upper = self.upper.scatter_reduce(0, block, torch.hypot(far[:, 0], far[:, 1]) + error, "amin")
        self._spread()

    def keep(self, points: torch.Tensor, error: torch.Tensor) -> torch.Tensor:
        """Which nodes, of ``(N, 2)`` points and ``(N,)`` errors, may hold a pixel's nearest leaf: ``(N,)`` bool."""
        gap = to_window(points, self.window)
        slack = error + self.margin
        cell, near = self._cell(points, 3 * GRID, GRID)
        # beyond the cells: only the widest reach of the border tells
        fine = (gap <= 0) | torch.where(near, self.need[cell] <= slack, gap - slack <= self.widest)
        return fine & (gap - error <= self.whole)


__all__ = ["GRID", "WindowReach", "to_window"]
