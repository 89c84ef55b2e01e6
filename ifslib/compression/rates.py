"""What each field costs, and the partition chosen at a price per bit whose file, once coded, fits a budget.

The rate-distortion search (`partition.prune`) needs each leaf's bits before the file exists. For
fixed fields they are exact (`fixed_rates`). For range-coded ones they depend on the statistics of
the very code being chosen, so `choose` alternates: prune with the current prices, code the result,
read each field's mean cost back from the coder's ledger (`measured_rates`), prune again with those;
and it moves the bits aimed at by the ratio of the coded size to the budget until the coded file fits.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import torch

from ..errors import IFSError
from .code import Code
from .collage import Fit, assemble
from .config import RATE_ROUNDS, CodeOptions
from .domains import ISOMETRY_BITS, domain_bits, domain_step, lattice
from .fields import encode_fields
from .partition import LeafChoice, Pruned, leaves_in_order, prune_to_budget


@dataclass(frozen=True)
class Rates:
    """Bits per field, as the partition search prices them.

    Attributes
    ----------
    split : dict
        ``{size: (bits of a "leaf" flag, bits of a "split" flag)}``.
    flat : dict
        ``{size: (bits of "has a domain", bits of "flat")}``.
    s, iso : float
        A contrast level's and an isometry's bits (blocks with a domain).
    m : tuple
        A mean's bits, ``(with a domain, flat)``.
    domain : dict
        ``{size: bits of a domain}``.
    """

    split: dict
    flat: dict
    s: float
    m: tuple
    iso: float
    domain: dict

    def leaf(self, size: int) -> tuple[float, float]:
        """``(bits of a leaf with a domain, bits of a flat leaf)`` of ``size``, its split flag excluded."""
        with_domain = self.flat[size][0] + self.s + self.m[0] + self.iso + self.domain[size]
        return with_domain, self.flat[size][1] + self.m[1]


def fixed_rates(height: int, width: int, o: CodeOptions) -> Rates:
    """The exact prices of version 1's fields for a padded ``height x width`` code (s_bits tell flat from not)."""
    return Rates(split={size: (1.0, 1.0) for size in o.sizes}, flat={size: (o.s_bits, o.s_bits) for size in o.sizes},
                 s=0.0, m=(o.m_bits, o.m_bits), iso=ISOMETRY_BITS,
                 domain={size: domain_bits(height, width, size) for size in o.sizes})


def measured_rates(ledger: dict, prior: Rates) -> Rates:
    """Each field's mean bits in a coder's ``ledger`` (`entropy.Coder`), ``prior``'s where it saw none."""

    def mean(key, fallback):
        n, bits = ledger.get(key, (0, 0.0))
        return bits / n if n else fallback

    def pair(name, size, old):
        return tuple(mean((name, size, v), old[v]) for v in (0, 1))

    sizes = prior.domain
    return Rates(split={s: pair("split", s, prior.split[s]) for s in sizes},
                 flat={s: pair("flat", s, prior.flat[s]) for s in sizes},
                 s=mean(("s",), prior.s), m=(mean(("m", False), prior.m[0]), mean(("m", True), prior.m[1])),
                 iso=mean(("iso",), prior.iso),
                 domain={s: mean(("row", s), prior.domain[s] / 2) + mean(("col", s), prior.domain[s] / 2)
                         for s in sizes})


def zigzags(offset: np.ndarray, n: int) -> np.ndarray:
    """`entropy.zigzag` of every entry of an integer array."""
    v = offset % n
    signed = np.where(v > n // 2, v - n, v)
    return np.where(signed > 0, 2 * signed - 1, -2 * signed)


def domain_cost(models, height: int, width: int, size: int, y: np.ndarray, x: np.ndarray) -> torch.Tensor:
    """``(R, D)`` the bits of each domain for each range of ``size`` at rows ``y`` and columns ``x`` ``(R,)``,
    under ``models`` (`fields.Models`, as a coding ended) for a padded ``height x width`` code."""
    n_rows, n_cols = lattice(height, width, size)
    step = domain_step(height, width, size)
    r0 = np.clip(np.round((np.asarray(y) - size / 2) / step), 0, n_rows - 1).astype(np.int64)
    c0 = np.clip(np.round((np.asarray(x) - size / 2) / step), 0, n_cols - 1).astype(np.int64)
    row_bits = models.row[size].costs()[zigzags(np.arange(n_rows)[None] - r0[:, None], n_rows)]  # (R, rows)
    col_bits = models.col[size].costs()[zigzags(np.arange(n_cols)[None] - c0[:, None], n_cols)]  # (R, cols)
    return torch.as_tensor((row_bits[:, :, None] + col_bits[:, None, :]).reshape(len(r0), -1), dtype=torch.float32)


def leaf_choices(errors: dict, rates: Rates) -> dict[int, LeafChoice]:
    """``{size: LeafChoice}`` from ``{size: (2, rows, cols) errors}`` (with a domain, flat) at ``rates``."""
    out = {}
    for size, err in errors.items():
        bits = rates.leaf(size)
        out[size] = LeafChoice(err=err, bits=np.stack([np.full(err.shape[1:], bits[0]), np.full(err.shape[1:], bits[1])]))
    return out


def _code(tree: Pruned, fits: tuple[dict, dict], height: int, width: int, o: CodeOptions) -> Code:
    mapped, flat = fits
    H, W = -(-height // o.max_block) * o.max_block, -(-width // o.max_block) * o.max_block
    chosen = {}
    for size in o.sizes:
        f = torch.as_tensor(tree.flat[size].reshape(-1))
        a, b = mapped[size], flat[size]
        chosen[size] = Fit(*(torch.where(f, getattr(b, name), getattr(a, name))
                             for name in ("err", "domain", "iso", "s_idx", "m_idx")))
    return assemble(height, width, o, chosen, leaves_in_order(H, W, o, tree.split))


class Choice(NamedTuple):
    """What `choose` chose: the ``code``, its estimated squared error ``err``, the price of a bit ``lam``
    that chose it, the ``rates`` measured on it and the coder's ``models`` as its coding ended (None for
    fixed fields)."""

    code: Code
    err: float
    lam: float
    rates: Rates
    models: object


def choose(fits: tuple[dict, dict], height: int, width: int, o: CodeOptions, budget_bits: float,
           rates: Rates | None = None) -> Choice:
    """The code of least estimated error whose coded fields fit in ``budget_bits``, from each block's two fits.

    Parameters
    ----------
    fits : tuple
        ``({size: Fit with a domain}, {size: flat Fit})``, every aligned block of the padded image.
    height, width : int
        The image's size.
    budget_bits : float
        The most bits after the header (`Code.bits`).
    rates : Rates, optional
        The first prices (default: version 1's).
    """
    H, W = -(-height // o.max_block) * o.max_block, -(-width // o.max_block) * o.max_block
    errors = {size: np.stack([fits[0][size].err.reshape(H // size, W // size).numpy(),
                              fits[1][size].err.reshape(H // size, W // size).numpy()]) for size in o.sizes}
    rounds_priced = rates is not None
    rates, aim, best = rates or fixed_rates(H, W, o), budget_bits, None
    for _ in range(1 if o.coder == "fixed" else RATE_ROUNDS):
        tree = prune_to_budget(o, leaf_choices(errors, rates), aim, rates.split)
        code = _code(tree, fits, height, width, o)
        if o.coder == "fixed":
            return Choice(code, tree.err, tree.lam, rates, None)
        coded = encode_fields(code)
        bits = 8 * len(coded.payload)
        rates = measured_rates(coded.ledger, rates)
        if bits <= budget_bits and (best is None or tree.err < best.err):
            best = Choice(code, tree.err, tree.lam, rates, coded.models)
        # the next round prices with the rates just measured; what remains is the estimate's bias
        aim = budget_bits * tree.bits / max(bits, 1) if rounds_priced else budget_bits
        rounds_priced = True
    if best is None:
        raise IFSError(f"no partition's coded fields fit in {budget_bits:.0f} bits; ask for a higher rate")
    return best
