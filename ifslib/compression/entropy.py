"""Adaptive models and the range coder that store a code's fields in as few bits as their statistics allow.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math
from collections import defaultdict

import constriction
import numpy as np

from ..errors import IFSError
from .config import ADAPT_INCREMENT


class Adaptive:
    """A distribution over ``n`` symbols learnt as they pass: ``p(k) ∝ prior(k) + increment * count(k)``.

    Parameters
    ----------
    prior : np.ndarray
        ``(n,)`` positive pseudo-counts: the first symbol's distribution, and how slowly it is forgotten.
    """

    def __init__(self, prior: np.ndarray):
        self.counts = np.asarray(prior, dtype=np.float64).copy()
        if self.counts.ndim != 1 or len(self.counts) < 1 or not (self.counts > 0).all():
            raise IFSError("an adaptive model needs one positive pseudo-count per symbol")
        self.total = float(self.counts.sum())

    @classmethod
    def uniform(cls, n: int, weight: float = 1.0) -> "Adaptive":
        """``n`` equally likely symbols, ``weight`` pseudo-counts each."""
        return cls(np.full(max(1, n), weight))

    def probabilities(self) -> np.ndarray:
        return self.counts / self.total

    def update(self, k: int) -> None:
        self.counts[k] += ADAPT_INCREMENT
        self.total += ADAPT_INCREMENT


class Magnitude:
    """A distribution over ``0 .. n - 1`` for values likelier the smaller they are (a residual, an offset, zigzagged).

    As JPEG codes a DC difference: the value's class, its bit length (0 for 0, 1 for 1, 2 for 2-3, 3 for
    4-7, ...), through an `Adaptive` model of a dozen symbols, which learns from a few dozen blocks
    where a model of all ``n`` values would need thousands; then its place within the class, uniform.
    """

    def __init__(self, n: int):
        self.n = max(1, n)
        self.classes = Adaptive.uniform((self.n - 1).bit_length() + 1)

    def costs(self) -> np.ndarray:
        """``(n,)`` the bits each value would cost now: its class's and its place's."""
        bits = -np.log2(self.classes.probabilities())
        out = np.empty(self.n)
        for c in range(len(bits)):
            first, count = self.span(c)
            out[first:first + count] = bits[c] + np.log2(count)
        return out

    def span(self, c: int) -> tuple[int, int]:
        """The first value of class ``c`` and how many values it holds (the last class is cut at ``n``)."""
        first = 0 if c == 0 else 1 << (c - 1)
        return first, (1 if c == 0 else min(first, self.n - first))


def zigzag(v: int, n: int) -> int:
    """A value modulo ``n`` (a difference wrapped) -> ``0 .. n - 1``: 0, 1, -1, 2, -2, ... (the nearer 0, the smaller)."""
    v %= n
    signed = v - n if v > n // 2 else v
    return 2 * signed - 1 if signed > 0 else -2 * signed


def unzigzag(z: int, n: int) -> int:
    """The inverse of `zigzag`: ``0 .. n - 1`` -> the value modulo ``n``."""
    return ((z + 1) // 2 if z % 2 else -(z // 2)) % n


class Coder:
    """The symmetric face of the range coder: `Encoder` and `Decoder` share `code`; ``ledger`` adds up the bits.

    ``ledger[key]`` is ``[symbols, bits]``: how many symbols were coded under ``key`` and their ideal cost
    (``-log2 p``), which the rate-distortion search reads back as each field's price (`rates`).
    """

    def __init__(self):
        self.ledger: dict = defaultdict(lambda: [0, 0.0])

    def code(self, model: Adaptive, value: int | None, key=None) -> int:
        p = model.probabilities()
        if len(p) == 1:  # one possible symbol carries no information (and constriction needs two)
            return self._check(value, 1) if value is not None else 0
        symbol = self._code(constriction.stream.model.Categorical(p, perfect=False), value, len(p))
        if key is not None:
            entry = self.ledger[key]
            entry[0] += 1
            entry[1] -= math.log2(p[symbol])
        model.update(symbol)
        return symbol

    def code_magnitude(self, model: Magnitude, value: int | None, key=None) -> int:
        """Code ``value`` (0 .. n - 1) by its class and then its place in the class (`Magnitude`)."""
        c = self.code(model.classes, None if value is None else int(value).bit_length(), key)
        first, count = model.span(c)
        if count == 1:
            return first
        uniform = constriction.stream.model.Categorical(np.full(count, 1.0 / count), perfect=False)
        place = self._code(uniform, None if value is None else value - first, count)
        if key is not None:
            self.ledger[key][1] += math.log2(count)
        return first + place

    def _code(self, model, value, n: int) -> int:
        raise NotImplementedError

    @staticmethod
    def _check(value: int, n: int) -> int:
        value = int(value)
        if not 0 <= value < n:
            raise IFSError(f"a field's value {value} is outside its {n} symbols; the code is not a valid one")
        return value


class Encoder(Coder):
    def __init__(self):
        super().__init__()
        self.range = constriction.stream.queue.RangeEncoder()

    def _code(self, model, value, n: int) -> int:
        value = self._check(value, n)
        self.range.encode(value, model)
        return value

    def payload(self) -> bytes:
        """The coded words as big-endian bytes, the last word's trailing zero bytes dropped (`Decoder` restores them)."""
        return self.range.get_compressed().astype(">u4").tobytes().rstrip(b"\x00")


class Decoder(Coder):
    def __init__(self, payload: bytes):
        super().__init__()
        padded = payload + b"\x00" * (-len(payload) % 4)
        self.range = constriction.stream.queue.RangeDecoder(np.frombuffer(padded, dtype=">u4").astype(np.uint32))

    def _code(self, model, value, n: int) -> int:
        try:
            return int(self.range.decode(model))
        except (AssertionError, ValueError, RuntimeError) as exc:
            raise IFSError(f"the file is corrupt (its coded fields do not decode: {exc})") from None
