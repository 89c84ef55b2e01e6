"""The decoder: iterate the code's operator from any start until the image stops changing, at any scale
that is a multiple of 2 / min_block (0.5, 1, 1.5, 2, ... for 4 px blocks: `check_scale`).

One iteration averages the image down by 2 x 2 and, for every range block, takes its domain's pixels
(under its isometry), centres them and sets ``s (D - mean D) + m``: a gather per block size, so an
iteration of a 256² code is a few array operations. At scale S every block and domain is S times
larger, so the same code draws a larger image (the "resolution independence" of fractal codes).
"""
from __future__ import annotations

from dataclasses import dataclass

import torch
import torch.nn.functional as F

from ..errors import IFSError
from .code import Code
from .config import DECODE_MAX_ITER, DECODE_TOL
from .deblock import deblock
from .domains import downsample
from .rectangles import isometry_count, rectangle_isometry, rectangle_lattice, rectangle_step


@dataclass(frozen=True)
class Group:
    """The blocks of one size: which leaves, and where each pixel comes from (``src``, ``(L, n)``, in the
    half-size image) and goes to (``dst``, ``(L, n)``, in the output)."""

    leaves: torch.Tensor
    src: torch.Tensor
    dst: torch.Tensor


@dataclass(frozen=True)
class Plan:
    """Where every pixel of one iteration comes from, for a code decoded at one scale."""

    height: int  # the padded output
    width: int
    crop: tuple[int, int]  # the image's own size at this scale
    groups: tuple[Group, ...]
    order: torch.Tensor  # (height * width,) output pixel -> position among the groups' concatenated pixels


def check_scale(scale, code: Code) -> float:
    """``scale`` if every block and domain lands on whole pixels at it, else `IFSError` saying which scales do."""
    step = 2 / code.options.min_block
    try:
        ok = scale > 0 and abs(scale / step - round(scale / step)) < 1e-9
    except TypeError:
        ok = False
    if not ok:
        raise IFSError(f"scale must be a positive multiple of {step:g} for a code with {code.options.min_block} px "
                       f"blocks (a domain must start on a whole pixel), got {scale!r}")
    return float(scale)


def shapes(code: Code) -> list[tuple[int, int]]:
    """The code's block shapes ``(height, width)``, largest first (a quadtree's: its sizes)."""
    pairs = torch.stack([code.heights, code.widths], 1).unique(dim=0).tolist()
    return sorted((tuple(p) for p in pairs), key=lambda p: (-p[0] * p[1], -p[0]))


def plan(code: Code, scale: float = 1.0) -> Plan:
    """The gather indices of one decoding iteration of ``code`` at ``scale``."""
    scale = check_scale(scale, code)
    H, W = (round(n * scale) for n in code.padded)
    half_w = W // 2
    groups, placed = [], []
    for bh, bw in shapes(code):
        leaves = torch.nonzero((code.heights == bh) & (code.widths == bw))[:, 0]
        rows_a, cols_a = torch.arange(round(bh * scale)), torch.arange(round(bw * scale))
        _, cols = rectangle_lattice(*code.padded, bh, bw)
        y, x = code.y[leaves] * scale, code.x[leaves] * scale
        dst = ((y.round().long()[:, None, None] + rows_a[:, None]) * W
               + x.round().long()[:, None, None] + cols_a).reshape(len(leaves), -1)
        sy, sx = (round(step * scale) // 2 for step in rectangle_step(*code.padded, bh, bw))
        d = code.domain[leaves]
        hy, hx = (d // cols) * sy, (d % cols) * sx
        grid = rows_a[:, None] * half_w + cols_a
        offsets = torch.stack([rectangle_isometry(grid, k).reshape(-1) for k in range(isometry_count(bh, bw))])
        src = (hy * half_w + hx)[:, None] + offsets[code.iso[leaves]]
        groups.append(Group(leaves, src, dst))
        placed.append(dst.reshape(-1))
    order = torch.empty(H * W, dtype=torch.long)
    order[torch.cat(placed)] = torch.arange(H * W)
    return Plan(H, W, (round(code.height * scale), round(code.width * scale)), tuple(groups), order)


def block_labels(p: Plan) -> torch.Tensor:
    """``(height, width)`` int64: each pixel of the plan's padded image labelled by its range block."""
    label = torch.empty(p.height * p.width, dtype=torch.long)
    for g in p.groups:
        label[g.dst] = g.leaves[:, None]
    return label.reshape(p.height, p.width)


def post_filter(p: Plan, x: torch.Tensor, weight: float) -> torch.Tensor:
    """The padded fixed point ``x`` as the decoder outputs it: its block seams smoothed at ``weight`` (`deblock`;
    0: ``x`` itself, no labels built)."""
    return deblock(block_labels(p), x, weight) if weight else x


def iterate(p: Plan, image: torch.Tensor, s: torch.Tensor, m: torch.Tensor) -> torch.Tensor:
    """One application of the operator: ``(H, W)`` -> ``(H, W)`` (padded), differentiable in image, s and m.

    Parameters
    ----------
    p : Plan
    image : torch.Tensor
        ``(H, W)`` the current padded image.
    s, m : torch.Tensor
        ``(L,)`` each block's contrast and mean.
    """
    half = downsample(image).reshape(-1)
    parts = []
    for g in p.groups:
        v = half[g.src]
        v = v - v.mean(1, keepdim=True)
        parts.append((s[g.leaves, None] * v + m[g.leaves, None]).reshape(-1))
    return torch.cat(parts)[p.order].reshape(p.height, p.width)


def domain_means(p: Plan, image: torch.Tensor) -> torch.Tensor:
    """``(L,)`` the mean of each block's averaged domain in ``image`` ``(H, W)`` (padded)."""
    half = downsample(image).reshape(-1)
    means = torch.empty(sum(len(g.leaves) for g in p.groups), dtype=image.dtype)
    for g in p.groups:
        means[g.leaves] = half[g.src].mean(1)
    return means


def iterate_offset(p: Plan, image: torch.Tensor, s: torch.Tensor, o: torch.Tensor) -> torch.Tensor:
    """One application of the classic, uncentred form ``s D + o`` (Jacquin's): ``(H, W)`` -> ``(H, W)``.

    It contracts the largest pixel difference by ``max |s|``; the coder stores the centred form of
    `iterate`, whose means are fixed by the file. With ``o = m - s * domain_means(p, x)`` both forms
    agree at ``x``.
    """
    half = downsample(image).reshape(-1)
    parts = [(s[g.leaves, None] * half[g.src] + o[g.leaves, None]).reshape(-1) for g in p.groups]
    return torch.cat(parts)[p.order].reshape(p.height, p.width)


def start_image(p: Plan, start, dtype) -> torch.Tensor:
    """The padded ``(H, W)`` first iterate: mid-gray when ``start`` is None, else ``start`` resized (bilinear)."""
    if start is None:
        return torch.full((p.height, p.width), 0.5, dtype=dtype)
    start = torch.as_tensor(start, dtype=dtype)
    if start.ndim != 2:
        raise IFSError(f"a start image must be (h, w) gray levels, got shape {tuple(start.shape)}")
    return F.interpolate(start[None, None], size=(p.height, p.width), mode="bilinear", align_corners=False)[0, 0]


@dataclass(frozen=True)
class Decoded:
    """A decoding: the ``image`` ``(h, w)`` (post-filtered by the code's ``deblock``, cropped to the code's
    size at the scale, clipped to [0, 1]), the ``padded`` fixed point ``(H, W)`` (unfiltered, unclipped),
    the ``iterations`` run and the last ``change``."""

    image: torch.Tensor
    padded: torch.Tensor
    iterations: int
    change: float


def fixed_point(p: Plan, s: torch.Tensor, m: torch.Tensor, start: torch.Tensor,
                tol: float = DECODE_TOL, max_iter: int = DECODE_MAX_ITER) -> tuple[torch.Tensor, int, float]:
    """Iterate from ``start`` ``(H, W)`` until no pixel moves more than ``tol``: ``(image, iterations, change)``."""
    x, change = start, float("inf")
    for k in range(1, max_iter + 1):
        new = iterate(p, x, s, m)
        change = float((new - x).abs().max())
        x = new
        if change <= tol:
            return x, k, change
    return x, max_iter, change


def decode(code: Code, scale: float = 1.0, start=None, tol: float = DECODE_TOL,
           max_iter: int = DECODE_MAX_ITER, dtype=torch.float32) -> Decoded:
    """Decode ``code`` at ``scale`` by iterating its operator from ``start`` (mid-gray by default).

    Parameters
    ----------
    code : Code
    scale : float
        Output pixels per image pixel (a multiple of 2 / min_block: 0.5, 1, 1.5, 2, ... for 4 px blocks).
    start : array, optional
        Any ``(h, w)`` image to start from (resized to the output); the fixed point does not depend on it.
    tol : float
        Stop when no pixel changed by more than this in one iteration.
    max_iter : int

    Returns
    -------
    Decoded
    """
    if not (tol > 0 and isinstance(max_iter, int) and max_iter >= 1):
        raise IFSError(f"tol must be > 0 and max_iter an integer >= 1, got {tol!r} and {max_iter!r}")
    p = plan(code, scale)
    with torch.no_grad():
        x, k, change = fixed_point(p, code.s(dtype), code.m(dtype), start_image(p, start, dtype), tol, max_iter)
    h, w = p.crop
    return Decoded(post_filter(p, x, code.options.deblock)[:h, :w].clamp(0, 1), x, k, change)
