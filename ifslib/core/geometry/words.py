"""The words of a cut of the word tree: stored whole (`DenseWords`) or as links to each node's parent (`WordTree`,
which spells out only the words asked for: copying every open node's word at each level costs O(nodes x length))."""
from __future__ import annotations

from dataclasses import dataclass, field

import torch


@dataclass
class DenseWords:
    """Words stored whole: ``(L, K)`` digits, padded with ``m`` (the identity)."""

    table: torch.Tensor

    @property
    def length(self) -> int:
        """The longest word's length ``K``."""
        return self.table.shape[1]

    def select(self, index: torch.Tensor) -> torch.Tensor:
        """The words of leaves ``index`` (``(N,)`` ids): ``(N, K)``."""
        return self.table.index_select(0, index)

    def all(self) -> torch.Tensor:
        return self.table

    def subset(self, index: torch.Tensor) -> "DenseWords":
        return DenseWords(self.table.index_select(0, index))


@dataclass
class WordTree:
    """Words as parent links: level ``k`` holds ``(N_k,)`` parents (ids among level ``k - 1``'s nodes; level 0 is
    the root, the empty word) and digits; each leaf is a node ``(level, id)``.

    Attributes
    ----------
    parents, digits : list of torch.Tensor
        Per level from 1: ``(N_k,)`` long and ``(N_k,)`` digits (uint8, or int16 above 255 maps).
    level, node : torch.Tensor
        ``(L,)`` long: each leaf's level (its word's length) and its id in that level.
    pad : int
        The padding digit ``m``.
    longest : int
        The words' padded length ``K`` (at least the longest leaf's).
    """

    pad: int
    dtype: torch.dtype
    longest: int = 0
    parents: list = field(default_factory=list)
    digits: list = field(default_factory=list)
    level: torch.Tensor | None = None
    node: torch.Tensor | None = None

    @property
    def length(self) -> int:
        """The words' padded length ``K``."""
        return self.longest

    def select(self, index: torch.Tensor) -> torch.Tensor:
        """The words of leaves ``index`` (``(N,)`` ids): ``(N, K)``, padded with ``pad``."""
        level, node = self.level.index_select(0, index), self.node.index_select(0, index)
        out = torch.full((index.numel(), self.length), self.pad, dtype=self.dtype, device=level.device)
        for k in range(int(level.max()) if level.numel() else 0, 0, -1):  # walk every leaf up to the root
            at = (level >= k).nonzero().flatten()
            out[at, k - 1] = self.digits[k - 1][node[at]]
            node[at] = self.parents[k - 1][node[at]]
        return out

    def all(self) -> torch.Tensor:
        return self.select(torch.arange(self.level.numel(), device=self.level.device))

    def subset(self, index: torch.Tensor) -> "WordTree":
        return WordTree(self.pad, self.dtype, self.longest, self.parents, self.digits, self.level[index],
                        self.node[index])


__all__ = ["DenseWords", "WordTree"]
