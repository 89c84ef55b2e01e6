"""The no-grad search for each pixel's nearest leaf: exact, and O(pixels + leaves) in memory, by a quadtree
pruned with the leaves' Lipschitz bound and tangent planes (docs/guide/design.md)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import torch

from ...errors import IFSError
from ..geometry.leaves import Leaves
from .leaf_distance import has_slope, leaf_table, sdf_pairs, sdf_table, sdf_table_slope

#: How many ulps (of 1, in plane units) rounding may move a leaf's gradient's vector, for the tangent plane's
#: error (`_lower`): float32 against float64 on the notebooks' leaves never exceeded 0.66.
ROUNDING_ULPS = 16
#: Above this many (block, leaf) pairs a level is processed in chunks of blocks.
MAX_PAIRS = 1 << 20
#: The walk starts at the deepest level whose blocks x leaves stay within this many pairs: with few
#: leaves the top levels prune little and cost only per-level overhead.
START_PAIRS = 1 << 14


@dataclass
class NearestResult:
    """Outcome of `nearest_leaf`: each pixel's nearest ``leaf`` id (row-major; item-major with the batch's global
    ids for batched leaves), its signed ``distance`` (no gradient) and the number of (block, leaf) ``pairs`` evaluated."""

    leaf: torch.Tensor
    distance: torch.Tensor
    pairs: int


def pixel_centres(size: int, device: torch.device | str = "cpu", dtype: torch.dtype = torch.float64,
                  window: tuple[float, float, float, float] | None = None):
    """Pixel-centre coordinates ``x, y`` ``(size * size,)`` of a ``size x size`` image of ``window`` (the frame when
    None), row-major, row 0 at the top (docs/guide/conventions.md)."""
    t = (torch.arange(size, device=device, dtype=dtype) + 0.5) / size
    if window is None:
        x, y = t - 0.5, 0.5 - t  # row r has y = 0.5 - (r + 0.5) / size
    else:
        x0, y0, x1, y1 = window
        x, y = x0 + t * (x1 - x0), y1 - t * (y1 - y0)
    return x.repeat(size), y.repeat_interleave(size)


def nearest_point(points: torch.Tensor, x: torch.Tensor, y: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """The nearest of ``points`` to each query ``(x, y)`` by a KD-tree (point leaves are many and tiny): index and distance."""
    from scipy.spatial import cKDTree

    tree = cKDTree(points.detach().cpu().double().numpy(), balanced_tree=False, compact_nodes=False)
    query = torch.stack([x.detach(), y.detach()], 1).cpu().double().numpy()
    # the queries are independent: as many workers as torch has threads (`ifslib.threads`)
    dist, index = tree.query(query, workers=max(1, torch.get_num_threads()))
    return (torch.from_numpy(index).to(points.device), torch.from_numpy(dist).to(device=x.device, dtype=x.dtype))


@torch.no_grad()
def nearest_leaf(leaves: Leaves, size: int, max_pairs: int = MAX_PAIRS) -> NearestResult:
    """Find the nearest leaf of every pixel centre, exactly (each batch item's pixels among its own leaves); a level
    over ``max_pairs`` pairs is split; `IFSError` when a pixel ends with no leaf."""
    tree = _quadtree(leaves.detach(), size)
    n_pixels = tree.n_items * size * size
    best_leaf = torch.full((n_pixels,), -1, dtype=torch.long, device=tree.device)
    best_dist = torch.full((n_pixels,), math.inf, dtype=tree.dtype, device=tree.device)
    stack, evaluated = [_first_task(tree)], 0
    while stack:
        task = stack.pop()
        d, slope, dmin, best = _block_minimum(tree, task)
        evaluated += d.numel()
        if task.level == tree.top:
            pix = (task.items * size + task.rows) * size + task.cols
            best_leaf[pix], best_dist[pix] = best, dmin
        else:
            stack += _children(tree, task, d, slope, best, max_pairs)
    lost = ((best_leaf < 0) | (best_leaf >= tree.n_leaves)).sum().item()
    if lost:
        # only a distance that is not finite (or not 1-Lipschitz) can leave a pixel without a leaf
        raise IFSError(f"the nearest-leaf search found no leaf for {lost} pixel(s): a leaf's distance is not "
                       "finite there (a degenerate map?)")
    return NearestResult(best_leaf, best_dist, evaluated)


class _Task(NamedTuple):
    """Blocks of one level of the quadtree and their candidate leaves, as (block, leaf) pairs."""

    level: int
    items: torch.Tensor  # (blocks,) the batch item each block belongs to
    rows: torch.Tensor  # (blocks,) the block's row and column at its level
    cols: torch.Tensor
    pair_block: torch.Tensor  # (pairs,) each pair's block
    pair_leaf: torch.Tensor  # (pairs,) each pair's leaf id


@dataclass(frozen=True)
class _Quadtree:
    """What every step of the walk shares: the leaves, the image and the quadtree over it."""

    leaves: Leaves
    size: int
    side: int  # the quadtree covers the next power of two
    top: int  # the level whose blocks are single pixels
    start: int  # the level the walk starts at
    n_leaves: int
    n_items: int
    per_item: int
    slack: float  # absorbs float32 rounding in the pruning test
    rounding: float  # E: how far rounding moves a coordinate, plane units (`_lower`)
    quad_r: torch.Tensor  # (4,) each child's row and column offset in its parent
    quad_c: torch.Tensor
    table: torch.Tensor | None  # `leaf_table`, None for mixed primitives
    slopes: bool  # whether the table gives the distances' gradients (`has_slope`)

    @property
    def device(self) -> torch.device:
        return self.leaves.inverse.device

    @property
    def dtype(self) -> torch.dtype:
        return self.leaves.inverse.dtype


def _quadtree(leaves: Leaves, size: int) -> _Quadtree:
    """The search's frame for ``leaves`` (detached) at ``size``."""
    device, dtype = leaves.inverse.device, leaves.inverse.dtype
    n_items = leaves.n_items
    per_item = len(leaves) // n_items
    side = 1 << max(size - 1, 0).bit_length()
    top = side.bit_length() - 1
    start = 0
    while start < top and 4 ** (start + 1) * per_item <= START_PAIRS:
        start += 1
    table = leaf_table(leaves)
    return _Quadtree(leaves=leaves, size=size, side=side, top=top, start=start, n_leaves=len(leaves),
                     n_items=n_items, per_item=per_item, slack=1e-5 if dtype == torch.float32 else 1e-12,
                     rounding=ROUNDING_ULPS * torch.finfo(dtype).eps,
                     quad_r=torch.tensor([0, 0, 1, 1], device=device),
                     quad_c=torch.tensor([0, 1, 0, 1], device=device),
                     table=table, slopes=has_slope(table, leaves.kinds[0]))


def _centres(tree: _Quadtree, rows: torch.Tensor, cols: torch.Tensor, block: int
             ) -> tuple[torch.Tensor, torch.Tensor]:
    """The plane coordinates ``x, y`` of the centres of the blocks ``(rows, cols)``, ``block`` pixels a side."""
    off = (block - 1) / 2 + 0.5
    size, dtype = tree.size, tree.dtype
    return -0.5 + (cols.to(dtype) * block + off) / size, 0.5 - (rows.to(dtype) * block + off) / size


def _distances(tree: _Quadtree, x: torch.Tensor, y: torch.Tensor, leaf: torch.Tensor) -> torch.Tensor:
    """The signed distance of leaf ``leaf[i]`` at ``(x[i], y[i])``."""
    if tree.table is None:
        return sdf_pairs(tree.leaves, x, y, leaf)
    return sdf_table(tree.table, tree.leaves.kinds[0], x, y, leaf)


def _first_task(tree: _Quadtree) -> _Task:
    """The blocks of the starting level that overlap the image, each paired with every leaf of its item."""
    device, start, side, size = tree.device, tree.start, tree.side, tree.size
    grid = torch.arange(1 << start, device=device)
    rows, cols = grid.repeat_interleave(1 << start), grid.repeat(1 << start)
    inside = (rows * (side >> start) < size) & (cols * (side >> start) < size)
    rows, cols = rows[inside].repeat(tree.n_items), cols[inside].repeat(tree.n_items)
    # every block belongs to one item (one point set of a batch) and pairs only with its leaves
    items = torch.arange(tree.n_items, device=device).repeat_interleave(rows.numel() // tree.n_items)
    per_item = tree.per_item
    return _Task(start, items, rows, cols, torch.arange(rows.numel(), device=device).repeat_interleave(per_item),
                 (items[:, None] * per_item + torch.arange(per_item, device=device)).flatten())


def _block_minimum(tree: _Quadtree, task: _Task):
    """Each pair's distance at its block's centre (with gradients and reaches where the table gives them), and each
    block's least one and the smallest leaf id at it."""
    n_blocks, device, dtype = task.rows.numel(), tree.device, tree.dtype
    bx, by = _centres(tree, task.rows, task.cols, tree.side >> task.level)
    x, y = bx.index_select(0, task.pair_block), by.index_select(0, task.pair_block)
    slope = None
    if tree.slopes and task.level < tree.top:
        d, *slope = sdf_table_slope(tree.table, tree.leaves.kinds[0], x, y, task.pair_leaf)
    else:
        d = _distances(tree, x, y, task.pair_leaf)
    dmin = torch.full((n_blocks,), math.inf, dtype=dtype, device=device)
    dmin = dmin.scatter_reduce(0, task.pair_block, d, "amin")
    # the smallest leaf id at the minimum of each block (at a pixel: its nearest leaf)
    best = torch.full((n_blocks,), tree.n_leaves, dtype=torch.long, device=device)
    at_min = torch.where(d <= dmin.index_select(0, task.pair_block), task.pair_leaf, tree.n_leaves)
    best = best.scatter_reduce(0, task.pair_block, at_min, "amin")
    return d, slope, dmin, best


def _children(tree: _Quadtree, task: _Task, d: torch.Tensor, slope, best: torch.Tensor, max_pairs: int) -> list[_Task]:
    """The next level's tasks: each block's children that overlap the image, with the pairs that pass the pruning."""
    level, items, rows, cols, pair_block, pair_leaf = task
    size, block = tree.size, tree.side >> level
    # Children that overlap the image. For child c of block b, the block's best leaf j0 gives
    # an upper bound U_c = d_j0(c) + h_c on every pixel's nearest distance in c, and any leaf's
    # distance over c is at least d_j(b) - h_b (1-Lipschitz; h = centre-to-farthest-pixel
    # distance). So (b, j) passes to c only if d_j(b) - h_b <= U_c.
    child = block // 2
    child_half_diag = (child - 1) / 2 * math.sqrt(2) / size
    child_items = items.repeat_interleave(4)
    child_rows = (2 * rows[:, None] + tree.quad_r).flatten()
    child_cols = (2 * cols[:, None] + tree.quad_c).flatten()
    inside = (child_rows * child < size) & (child_cols * child < size)
    cx, cy = _centres(tree, child_rows, child_cols, child)
    bound = _distances(tree, cx, cy, best.repeat_interleave(4)) + child_half_diag
    bound = torch.where(inside, bound, -math.inf).view(-1, 4)
    passes = _lower(tree, d, slope, level) <= bound.index_select(0, pair_block)  # (pairs, 4)
    child_id = torch.where(inside, torch.cumsum(inside.long(), 0) - 1, -1).view(-1, 4)
    hit = passes.view(-1).nonzero().squeeze(1)  # pair * 4 + quadrant of every pair that passes
    pair = hit >> 2
    new_block = child_id.view(-1).index_select(0, pair_block.index_select(0, pair) * 4 + (hit & 3))
    new_leaf = pair_leaf.index_select(0, pair)
    children = _Task(level + 1, child_items[inside], child_rows[inside], child_cols[inside], new_block, new_leaf)
    return _chunks(children, max_pairs)


def _lower(tree: _Quadtree, d: torch.Tensor, slope, level: int) -> torch.Tensor:
    """A lower bound of each pair's distance over the pixel centres of each of its block's four children:
    ``(pairs, 1)`` from the Lipschitz bound, ``(pairs, 4)`` from the tangent plane when ``slope`` is given."""
    size, block = tree.size, tree.side >> level
    half_diag = (block - 1) / 2 * math.sqrt(2) / size  # from the block's centre to its farthest pixel centre
    lipschitz = (d - half_diag - tree.slack)[:, None]
    if slope is None:
        return lipschitz
    gx, gy, reach = slope
    # A computed gradient is off by up to 2 E / reach (`sdf_table_slope`), and so the plane by that times
    # the distance moved; where that eats the gain (a pixel on a segment's spine) the Lipschitz bound wins.
    wobble = (2 * tree.rounding / reach).clamp_max(2) * half_diag
    # A child's centre lies (±a, ±a) from the block's (plane units, y upward); its pixel centres lie within
    # ``corner`` of it along each axis, so the plane's least value over them is at a corner of their box.
    a, corner = (block // 2) / 2 / size, (block // 2 - 1) / 2 / size
    base = d - (gx.abs() + gy.abs()) * corner - wobble - tree.slack
    up, down = a * (gx + gy), a * (gx - gy)
    # the children in `_Quadtree.quad_r` / ``quad_c``'s order: top left, top right, bottom left, bottom right
    plane = torch.stack([base - down, base + up, base - up, base + down], 1)
    return torch.maximum(plane, lipschitz)


def _chunks(task: _Task, max_pairs: int) -> list[_Task]:
    """``task`` split into runs of consecutive blocks when it has more than ``max_pairs`` pairs (bounds memory)."""
    level, items, rows, cols, new_block, new_leaf = task
    n_chunks = max(1, math.ceil(new_block.numel() / max_pairs))
    bounds = torch.linspace(0, rows.numel(), n_chunks + 1).round().long().tolist()
    out = []
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        sel = ((new_block >= lo) & (new_block < hi)) if n_chunks > 1 else slice(None)
        out.append(_Task(level, items[lo:hi], rows[lo:hi], cols[lo:hi], new_block[sel] - lo, new_leaf[sel]))
    return out
