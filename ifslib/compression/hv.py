"""The HV partition chosen by rate and distortion: rectangles cut at their strongest edge, pruned to a budget.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import torch

from ..errors import IFSError
from .code import Code
from .collage import search
from .config import PRUNE_ROUNDS, RATE_ROUNDS, CodeOptions
from .fields import encode_fields
from .entropy import Encoder
from .hvfields import code_hv_fields, hv_columns
from .partition import cheapest_fit
from .partitions import Partition
from .quantize import dequantize_m, quantize_m, zero_s
from .rates import Choice
from .rectangles import Block, cut_positions, edge_split, isometry_count, rectangle_isometry, rectangle_pool, split_block


@dataclass(frozen=True)
class Tree:
    """The full HV tree: ``blocks``, each node's ``kids`` (two indices or None), and per node ``err`` and
    ``bits`` ``(N, 2)`` (with a domain, flat), ``fits`` ``(N, 2, 4)`` (domain, iso, s_idx, m_idx), the split
    flag's bits as a leaf and as a cut node (``leaf_flag``, ``cut_bits``: 0 for a leaf that cannot be cut;
    a cut node's includes its axis and position), and the number of ``roots`` (the first nodes)."""

    blocks: list
    kids: list
    err: np.ndarray
    bits: np.ndarray
    fits: np.ndarray
    leaf_flag: np.ndarray
    cut_bits: np.ndarray
    roots: int


def full_tree(target: torch.Tensor, options: CodeOptions) -> tuple[list, list]:
    """Every ``max_block`` square of ``target`` ``(H, W)`` cut at its strongest edge down to uncuttable blocks."""
    b, (H, W) = options.max_block, target.shape
    blocks = [Block(y, x, b, b) for y in range(0, H, b) for x in range(0, W, b)]
    kids = [None] * len(blocks)
    i = 0
    while i < len(blocks):
        y, x, h, w = blocks[i]
        cut = edge_split(target[y:y + h, x:x + w], options.min_block)
        if cut is not None:
            kids[i] = (len(blocks), len(blocks) + 1)
            blocks += list(split_block(blocks[i], *cut))
            kids += [None, None]
        i += 1
    return blocks, kids


def fit_nodes(target: torch.Tensor, pool_image: torch.Tensor, blocks: list, options: CodeOptions):
    """Each block's fit with a domain and flat: ``(err (N, 2), fits (N, 2, 4), domain bits (N,), isometry bits (N,))``."""
    n = len(blocks)
    err, fits = np.zeros((n, 2)), np.zeros((n, 2, 4), dtype=np.int64)
    dbits, ibits = np.zeros(n), np.zeros(n)
    by_shape: dict = {}
    for i, (_, _, h, w) in enumerate(blocks):
        by_shape.setdefault((h, w), []).append(i)
    width = target.shape[1]
    for (h, w), at in by_shape.items():
        at_t = np.asarray(at)
        ys, xs = (torch.tensor([blocks[i][k] for i in at]) for k in (0, 1))
        rows = (ys[:, None, None] + torch.arange(h)[:, None]) * width + xs[:, None, None] + torch.arange(w)
        pix = target.reshape(-1)[rows.reshape(len(at), -1)]
        pool = rectangle_pool(pool_image, h, w)
        domains = torch.stack([rectangle_isometry(pool, k).reshape(len(pool), -1) for k in range(isometry_count(h, w))])
        fit = search(pix, domains, options, torch.ones(len(at), dtype=torch.bool))
        m_idx = quantize_m(pix.mean(1), options)
        flat_err = ((pix - dequantize_m(m_idx, options, pix.dtype)[:, None]) ** 2).sum(1).double()
        err[at_t, 0], err[at_t, 1] = fit.err.numpy(), flat_err.numpy()
        fits[at_t, 0] = torch.stack([fit.domain, fit.iso, fit.s_idx, fit.m_idx], 1).numpy()
        fits[at_t, 1] = torch.stack([0 * m_idx, 0 * m_idx, torch.full_like(m_idx, zero_s(options)), m_idx], 1).numpy()
        dbits[at_t], ibits[at_t] = math.log2(max(2, len(pool))), math.log2(isometry_count(h, w))
    return err, fits, dbits, ibits


def tree(target: torch.Tensor, pool_image: torch.Tensor, options: CodeOptions) -> Tree:
    """The full HV tree of ``target`` with every node fitted from ``pool_image`` and priced at fixed bits."""
    blocks, kids = full_tree(target, options)
    err, fits, dbits, ibits = fit_nodes(target, pool_image, blocks, options)
    o = options
    bits = np.stack([1 + o.s_bits + o.m_bits + dbits + ibits, 1 + o.m_bits + 0 * dbits], 1)
    flag = np.array([1.0 if cut_positions(h, o.min_block) or cut_positions(w, o.min_block) else 0.0
                     for _, _, h, w in blocks])
    cut_bits = flag + np.array([math.log2(max(1, len(cut_positions(h, o.min_block)) + len(cut_positions(w, o.min_block))))
                                for _, _, h, w in blocks])
    roots = (target.shape[0] // o.max_block) * (target.shape[1] // o.max_block)
    return Tree(blocks, kids, err, bits, fits, flag, cut_bits, roots)


def prune(t: Tree, lam: float) -> tuple[list, float, float]:
    """The leaves (``(node, flat?)``) of least ``err + lam * bits`` under every root: ``(leaves, bits, err)``."""
    n = len(t.blocks)
    cost, err, bits = np.zeros(n), np.zeros(n), np.zeros(n)
    split, flat = np.zeros(n, bool), np.zeros(n, bool)
    leaf_cost = t.err + lam * t.bits
    for i in range(n - 1, -1, -1):
        k = int(leaf_cost[i, 1] < leaf_cost[i, 0])
        flat[i] = bool(k)
        cost[i], err[i], bits[i] = leaf_cost[i, k] + lam * t.leaf_flag[i], t.err[i, k], t.bits[i, k] + t.leaf_flag[i]
        if t.kids[i] is not None:
            a, b = t.kids[i]
            extra = t.cut_bits[i]
            if cost[a] + cost[b] + lam * extra < cost[i]:
                split[i] = True
                cost[i], err[i], bits[i] = cost[a] + cost[b] + lam * extra, err[a] + err[b], bits[a] + bits[b] + extra
    roots = list(range(t.roots))
    leaves, stack = [], list(reversed(roots))
    while stack:
        i = stack.pop()
        if split[i]:
            stack += list(reversed(t.kids[i]))
        else:
            leaves.append((i, bool(flat[i])))
    return leaves, float(bits[roots].sum()), float(err[roots].sum())


def assemble(t: Tree, leaves: list, height: int, width: int, options: CodeOptions) -> Code:
    """The HV `Code` of the chosen ``leaves`` (``(node, flat?)``, depth first)."""
    rows = [(*t.blocks[i], *t.fits[i, int(f)]) for i, f in leaves]
    return in_file_order(Code(options, height, width, **hv_columns(rows)))


def in_file_order(code: Code) -> Code:
    """``code`` with its blocks in the order the file walks them (two cut sequences may give the same
    rectangles; the file's walk takes one of them, so a code read back is the code written)."""
    rows, _ = code_hv_fields(Encoder(), *code.padded, code.options, code)
    return Code(code.options, code.height, code.width, **hv_columns(rows))


def measured(t: Tree, ledger: dict) -> Tree:
    """``t`` priced at the mean bits each field took in a coding's ``ledger`` (`entropy.Coder`)."""
    def mean(key, fallback):
        n, bits = ledger.get(key, (0, 0.0))
        return bits / n if n else fallback

    with_domain = (mean(("flat", 0), 1) + mean(("s",), 5) + mean(("m", False), 6) + mean(("iso",), 2)
                   + mean(("row",), 3) + mean(("col",), 3))
    flat = mean(("flat", 1), 1) + mean(("m", True), 6)
    cuttable = t.leaf_flag > 0
    cut = mean(("split", 1), 1) + mean(("axis",), 1) + mean(("place",), 2)
    return replace(t, bits=np.stack([np.full(len(t.blocks), with_domain), np.full(len(t.blocks), flat)], 1),
                   leaf_flag=np.where(cuttable, mean(("split", 0), 1), 0.0), cut_bits=np.where(cuttable, cut, 0.0))


def hv_partition(target: torch.Tensor, pool_image: torch.Tensor, height: int, width: int, options: CodeOptions,
                 budget_bits: float, progress: bool = False) -> Choice:
    """The HV code of ``target`` ``(H, W)`` (padded) whose blocks map domains of ``pool_image``, in ``budget_bits``
    (`rates.Choice`, with no price of a bit: the range coder's models here are not the quadtree's).

    Parameters
    ----------
    target, pool_image : torch.Tensor
        ``(H, W)`` the padded image coded and the image its domains are cut from.
    height, width : int
        The image's own size.
    options : CodeOptions
        With ``partition="hv"``.
    budget_bits : float
        The most bits of the range-coded fields.
    progress : bool
        Unused: the search has no stage long enough for a bar.
    """
    t = tree(target, pool_image, options)
    aim, best, priced = budget_bits, None, False
    for _ in range(RATE_ROUNDS):
        leaves, estimate, err = cheapest_fit(lambda lam: prune(t, lam), lambda out: out[1], aim, PRUNE_ROUNDS // 2)
        code = assemble(t, leaves, height, width, options)
        coded = encode_fields(code)
        bits = 8 * len(coded.payload)
        if bits <= budget_bits and (best is None or err < best[1]):
            best = (code, err)
        # the next round prices with the bits just measured; what remains is the estimate's bias
        aim = budget_bits * estimate / max(bits, 1) if priced else budget_bits
        t, priced = measured(t, coded.ledger), True
    if best is None:
        raise IFSError(f"no HV partition's coded fields fit in {budget_bits:.0f} bits; ask for a higher rate")
    return Choice(best[0], float("nan"), 0.0, None, None)


#: rectangles, chosen at a rate only (no greedy growth to a collage quality)
PARTITION = Partition("hv", rectangles=True, fields=code_hv_fields, columns=hv_columns, at_rate=hv_partition)
