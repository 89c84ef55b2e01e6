"""The quadtree partition into range blocks: grown greedily where splitting buys the most error per bit.

A node is ``(size, row, column)``; the top nodes are the ``max_block`` squares in raster order, and a
split node's four children go top-left, top-right, bottom-left, bottom-right (the file's order).
"""
from __future__ import annotations

import heapq
from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np

from .config import PRUNE_ROUNDS, CodeOptions

Node = tuple[int, int, int]  # (size, y, x)


@dataclass(frozen=True)
class LevelCost:
    """What each aligned block of one size costs and leaves: ``err`` (squared error) and ``bits``, ``(rows, cols)``."""

    err: np.ndarray
    bits: np.ndarray


def top_nodes(height: int, width: int, options: CodeOptions) -> list[Node]:
    """The quadtree's roots for a padded ``height x width`` image, in raster order."""
    b = options.max_block
    return [(b, y, x) for y in range(0, height, b) for x in range(0, width, b)]


def children(node: Node) -> list[Node]:
    """The four quarters of ``node``, in the file's order."""
    size, y, x = node
    h = size // 2
    return [(h, y, x), (h, y, x + h), (h, y + h, x), (h, y + h, x + h)]


def leaves_in_order(height: int, width: int, options: CodeOptions, split: set[Node]) -> list[Node]:
    """The leaves of the quadtree whose split nodes are ``split``, depth first."""
    out: list[Node] = []

    def visit(node: Node) -> None:
        if node in split:
            for child in children(node):
                visit(child)
        else:
            out.append(node)

    for node in top_nodes(height, width, options):
        visit(node)
    return out


def walk(height: int, width: int, options: CodeOptions, is_split) -> Iterator[tuple[Node, bool]]:
    """Yield ``(node, split?)`` depth first, asking ``is_split(node)`` for every node above min_block."""
    stack = list(reversed(top_nodes(height, width, options)))
    while stack:
        node = stack.pop()
        split = node[0] > options.min_block and is_split(node)
        yield node, split
        if split:
            stack.extend(reversed(children(node)))


def _cost(costs: dict[int, LevelCost], node: Node) -> tuple[float, int]:
    size, y, x = node
    level = costs[size]
    return float(level.err[y // size, x // size]), int(level.bits[y // size, x // size])


def _split_price(costs: dict[int, LevelCost], node: Node, options: CodeOptions) -> tuple[float, int]:
    """Error saved and bits added by splitting ``node`` into four leaves."""
    err, bits = _cost(costs, node)
    kids = [_cost(costs, c) for c in children(node)]
    flags = 4 if node[0] // 2 > options.min_block else 0
    return err - sum(k[0] for k in kids), sum(k[1] for k in kids) + flags - bits


def grow(height: int, width: int, options: CodeOptions, costs: dict[int, LevelCost],
         budget_bits: float = float("inf"), target_err: float = 0.0) -> set[Node]:
    """Split nodes greedily, the most error saved per bit first, within ``budget_bits`` or until ``target_err``.

    Parameters
    ----------
    height, width : int
        The padded image (multiples of max_block).
    costs : dict
        ``{size: LevelCost}`` for every block size, from the collage search.
    budget_bits : float
        The most bits of flags and maps (the header excluded).
    target_err : float
        Stop once the total squared error is at most this.

    Returns
    -------
    set of Node
        The split nodes.
    """
    roots = top_nodes(height, width, options)
    flags = len(roots) if options.max_block > options.min_block else 0
    total_bits = flags + sum(_cost(costs, n)[1] for n in roots)
    total_err = sum(_cost(costs, n)[0] for n in roots)
    heap: list[tuple[float, Node]] = []

    def offer(node: Node) -> None:
        if node[0] > options.min_block:
            saved, added = _split_price(costs, node, options)
            if saved > 0:
                heapq.heappush(heap, (-saved / max(added, 1), node))

    for node in roots:
        offer(node)
    split: set[Node] = set()
    while heap and total_err > target_err:
        _, node = heapq.heappop(heap)
        saved, added = _split_price(costs, node, options)
        if total_bits + added > budget_bits:
            continue
        split.add(node)
        total_bits += added
        total_err -= saved
        for child in children(node):
            offer(child)
    return split


@dataclass(frozen=True)
class LeafChoice:
    """What each aligned block of one size costs as a leaf, stored with a domain or flat (its mean alone).

    ``err`` and ``bits`` are ``(2, rows, cols)``: index 0 with a domain, index 1 flat.
    """

    err: np.ndarray
    bits: np.ndarray


@dataclass(frozen=True)
class Pruned:
    """A quadtree chosen by `prune`: ``split``, the nodes split where reached (`leaves_in_order` walks them);
    ``flat``, ``{size: (rows, cols) bool}``, which blocks are stored flat when leaves; its ``bits`` (flags and
    maps, as priced: whole for fixed fields, estimated for coded ones) and ``err`` (total squared error)."""

    split: set
    flat: dict
    bits: float
    err: float
    lam: float = 0.0


def prune(options: CodeOptions, choices: dict[int, LeafChoice], lam: float, flags: dict | None = None) -> Pruned:
    """The quadtree and flat blocks of least ``err + lam * bits``, exactly, by dynamic programming from the leaves up.

    Greedy growth (`grow`) splits the best ratio first and never undoes a split or stores a block flat
    that has a usable domain; the optimum for a Lagrange multiplier ``lam`` (squared error per bit)
    weighs every subtree against its leaf (Sullivan and Baker's quadtree optimisation).

    Parameters
    ----------
    options : CodeOptions
    choices : dict
        ``{size: LeafChoice}`` for every block size, each on its size's grid of the padded image.
    lam : float
        The price of a bit, in squared error.
    flags : dict, optional
        ``{size: (bits of "leaf", bits of "split")}``, the split flag's price at each size above
        min_block (default: 1 bit either way, as version 1 stores it).
    """
    best: dict[int, tuple] = {}
    leaf_flat: dict[int, np.ndarray] = {}
    splits: dict[int, np.ndarray] = {}
    for size in reversed(options.sizes):  # smallest first
        c = choices[size]
        leaf_flag, split_flag = (flags or {}).get(size, (1, 1)) if size > options.min_block else (0, 0)
        total = c.err + lam * c.bits
        flat = total[1] < total[0]
        cost, err, bits = (np.where(flat, a[1], a[0]) for a in (total, c.err, c.bits))
        cost, bits = cost + lam * leaf_flag, bits + leaf_flag
        leaf_flat[size] = flat
        if size > options.min_block:
            rows, cols = cost.shape
            k_cost, k_err, k_bits = (a.reshape(rows, 2, cols, 2).sum((1, 3)) for a in best[size // 2])
            split = k_cost + lam * split_flag < cost
            splits[size] = split
            cost = np.where(split, k_cost + lam * split_flag, cost)
            err = np.where(split, k_err, err)
            bits = np.where(split, k_bits + split_flag, bits)
        best[size] = (cost, err, bits)
    _, err, bits = best[options.max_block]
    split_nodes = {(size, int(i) * size, int(j) * size)
                   for size, grid in splits.items() for i, j in zip(*np.nonzero(grid))}
    return Pruned(split_nodes, leaf_flat, float(bits.sum()), float(err.sum()), lam)


def prune_to_budget(options: CodeOptions, choices: dict[int, LeafChoice], budget_bits: float,
                    flags: dict | None = None) -> Pruned:
    """The `prune` of the smallest multiplier (bisected) whose tree fits in ``budget_bits``.

    Each `prune` is exact for its price of a bit, so the tree returned has the least error of any tree
    of at most its own bits. It is close to, but not always, the tree of least error within
    ``budget_bits``: a price reaches only the trees on the lower convex hull of (bits, error), and a
    tree off the hull may spend the few bits this one leaves unspent (a flat block given a domain,
    say) for less error. A tree of fewer bits than the coarsest one (every top block flat) does not
    exist: that one is returned, over the budget, if the budget is below it.
    """
    return cheapest_fit(lambda lam: prune(options, choices, lam, flags), lambda tree: tree.bits, budget_bits)


def cheapest_fit(prune_at: Callable, bits: Callable, budget_bits: float, rounds: int = PRUNE_ROUNDS):
    """``prune_at(lam)`` at the smallest price ``lam`` of a bit whose ``bits(...)`` fit ``budget_bits``: the
    price raised fourfold from 1e-3 until they fit, then bisected ``rounds`` times (either partition's pruning)."""
    lo, hi = 0.0, 1e-3
    for _ in range(60):
        if bits(prune_at(hi)) <= budget_bits:
            break
        lo, hi = hi, hi * 4
    best = prune_at(hi)
    for _ in range(rounds):
        mid = (lo + hi) / 2
        tree = prune_at(mid)
        if bits(tree) <= budget_bits:
            hi, best = mid, tree
        else:
            lo = mid
    return best
