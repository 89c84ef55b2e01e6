"""The quadtree partition into range blocks: grown greedily where splitting buys the most error per bit.

A node is ``(size, row, column)``; the top nodes are the ``max_block`` squares in raster order, and a
split node's four children go top-left, top-right, bottom-left, bottom-right (the file's order).
"""
from __future__ import annotations

import heapq
from dataclasses import dataclass
from typing import Iterator

import numpy as np

from .config import CodeOptions

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
