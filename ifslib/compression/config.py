"""The coder's settings: the quadtree's block sizes, the bits of each quantized number, and the tuned numbers.

`CodeOptions` is what a file's header records (the decoder needs it); `RefineOptions` is how hard the
attractor coder works, and is not stored.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import IFSError
from ..names import PARTITIONS  # the partitions, in the order a version 2 header numbers them

FIXED_PARTITION = next(iter(PARTITIONS))  #: the one partition file version 1 holds: its header names none

#: the largest ``|s|`` the coder may choose: below 1 keeps each map's classic form s D + o a contraction; the
#: centred form the file stores settles in a few passes anyway, and the bound keeps rounding from growing.
S_MAX = 0.95
#: bits of a block's contrast s: 32 levels S_MAX / 16 apart, from -S_MAX to 15/16 S_MAX (zero included);
#: fewer bits leave a coarser s, more cost every non-flat block a bit.
S_BITS = 5
#: bits of a block's mean gray level: 64 levels from 0 to 1 (an error of at most 1/126, 0.8 % of the range).
#: Range-coded, a level less saves about a bit a block: on benchmarks/compression.py's 18 cells at 256²,
#: attractor coding decoded 0.06 dB closer on average with 6 bits than with 7 (+0.14 dB at 0.15 bpp,
#: +0.07 at 0.25, -0.03 at 0.5); 5 bits lost 0.3 dB at 0.5 bpp (collage coder, three images).
M_BITS = 6
#: the largest range block, in pixels: larger saves bits on flat areas, costs a coarser first split.
MAX_BLOCK = 32
#: the smallest range block: a 4 px block costs about 25 bits (1.6 bits a pixel); 2 px ones would cost 6.
MIN_BLOCK = 4
#: the most domains per block size: more finds closer domains, at a search cost (and a domain index of
#: log2 of it bits); 1024 keeps every 4 px block of a 256² image searchable in about a second.
MAX_DOMAINS = 1024
#: the HV partition's split positions are multiples of this many pixels: 1 finds each edge exactly, larger
#: leaves fewer block shapes to pool domains for and fewer bits to code a position.
HV_STEP = 2
#: the file's coders: ``fixed`` (version 1, every field its bits) and ``adaptive`` (version 2, range-coded)
CODERS = ("fixed", "adaptive")
#: what an adaptive model adds to a symbol's count each time it is coded: larger learns faster from few
#: blocks (a 256² file at 0.15 bpp has about 400), smaller settles closer to the true frequencies.
ADAPT_INCREMENT = 1.0
#: the decoder's post-filter weight across block seams (`deblock`) that `method.compress` offers (kept per
#: file only if it decodes closer): larger hides the blocks' steps, and blurs edges that lie on a seam.
DEBLOCK = 0.15


@dataclass(frozen=True)
class CodeOptions:
    """How a code is laid out (stored in the file's header).

    Parameters
    ----------
    min_block, max_block : int
        The smallest and largest range blocks (powers of two, 4 <= min_block <= max_block <= 128).
        Domains are blocks twice as large on a lattice (`domains.domain_step`).
    s_bits, m_bits : int
        Bits of each block's contrast and of its mean gray level (2-8 and 4-10).
    s_max : float
        The largest ``|s|`` (0 < s_max < 1 keeps the decoder a contraction).
    coder : str
        How the file stores the fields, one of `CODERS`: ``"adaptive"`` (file version 2, the range coder
        of `fields`) or ``"fixed"`` (version 1, each field its bits).
    partition : str
        One of `PARTITIONS` (`partitions`): ``"quadtree"`` (square blocks) or ``"hv"`` (rectangles split
        at their strongest edge, sides from min_block up); the adaptive coder's, but for `FIXED_PARTITION`.
    deblock : float
        The decoder's post-filter (`deblock`): the weight, 0 to 0.5 in steps of 0.01, each pixel beside a
        block seam takes from the pixel across it (0: none; adaptive coder only, file version 3).
    """

    min_block: int = MIN_BLOCK
    max_block: int = MAX_BLOCK
    s_bits: int = S_BITS
    m_bits: int = M_BITS
    s_max: float = S_MAX
    coder: str = "adaptive"
    partition: str = "quadtree"
    deblock: float = 0.0

    def __post_init__(self):
        for name in ("min_block", "max_block"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 4 or value > 128 or value & (value - 1):
                raise IFSError(f"{name} must be a power of two from 4 to 128, got {value!r}")
        if self.min_block > self.max_block:
            raise IFSError(f"min_block ({self.min_block}) must not exceed max_block ({self.max_block})")
        for name, low, high in (("s_bits", 2, 8), ("m_bits", 4, 10)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
                raise IFSError(f"{name} must be an integer from {low} to {high}, got {value!r}")
        if not (isinstance(self.s_max, (int, float)) and 0 < self.s_max < 1):
            raise IFSError(f"s_max must be a number in (0, 1) (|s| < 1 keeps the decoder contracting), got {self.s_max!r}")
        if self.coder not in CODERS:
            raise IFSError(f"coder must be one of {', '.join(CODERS)}, got {self.coder!r}")
        if self.partition not in PARTITIONS:
            raise IFSError(f"partition must be one of {', '.join(PARTITIONS)}, got {self.partition!r}")
        if self.partition != FIXED_PARTITION and self.coder == "fixed":
            raise IFSError(f"the {self.partition} partition needs the adaptive coder (file version 2); version 1 "
                           f"holds the {FIXED_PARTITION} only")
        d = self.deblock
        if (isinstance(d, bool) or not isinstance(d, (int, float))
                or not (0 <= d <= 0.5 and abs(d * 100 - round(d * 100)) < 1e-9)):
            raise IFSError(f"deblock must be a number from 0 to 0.5 in steps of 0.01 (the file stores hundredths), "
                           f"got {d!r}")
        if d and self.coder == "fixed":
            raise IFSError("the deblocking filter needs the adaptive coder (file version 3); "
                           "version 1 cannot record it")

    @property
    def sizes(self) -> list[int]:
        """The range block sizes, largest first."""
        out, size = [], self.max_block
        while size >= self.min_block:
            out.append(size)
            size //= 2
        return out


@dataclass(frozen=True)
class RefineOptions:
    """How the attractor coder refines a collage code.

    Parameters
    ----------
    searches : int
        Rounds of the local search that picks each block's domain and isometry again from the decoded
        image (0: keep the collage's choices). Each round costs about one collage search.
    steps : int
        Adam steps on the quantized contrasts and means through the decoder's fixed point (0: none).
    lr : float
        Adam's step, in quantization levels.
    repartitions : int
        Rounds that choose the quadtree and the flat blocks again for the decoded image at no more bits
        (`repartition`), each followed by the two moves above (0: keep the collage coder's partition).
    """

    searches: int = 3
    steps: int = 30
    lr: float = 0.3
    repartitions: int = 1

    def __post_init__(self):
        for name in ("searches", "steps", "repartitions"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise IFSError(f"{name} must be an integer >= 0, got {value!r}")
        if not (isinstance(self.lr, (int, float)) and self.lr > 0):
            raise IFSError(f"lr must be a number > 0, got {self.lr!r}")


#: bisection steps on the price of a bit when pruning the quadtree to a budget (`partition.prune_to_budget`):
#: more land closer to the budget (fewer bits left unspent), each costs one pass over the block grids.
PRUNE_ROUNDS = 40
#: the decoder stops when no pixel changed by more than this (gray levels in [0, 1]) in one iteration.
DECODE_TOL = 1e-4
#: the decoder's cap on iterations: with ``|s| <= 0.95`` and the means stored, 10-20 usually suffice.
DECODE_MAX_ITER = 100
#: rounds of prune -> code -> measure the fields' bits -> prune again (`rates.choose`): each costs a
#: pruning bisection and one coding (about 0.05 s at 256²); more land closer to the budget.
RATE_ROUNDS = 5
