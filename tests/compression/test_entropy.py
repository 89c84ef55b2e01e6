"""The range coder's models: what is coded decodes back, the ledger counts the ideal bits, zigzag is a bijection."""
import numpy as np
import pytest

from ifslib.compression.entropy import Adaptive, Decoder, Encoder, Magnitude, unzigzag, zigzag
from ifslib.errors import IFSError


@pytest.mark.parametrize("n", [1, 2, 5, 8, 31, 128])
def test_zigzag_orders_a_wrapped_difference_by_its_size(n):
    z = [zigzag(v, n) for v in range(n)]
    assert sorted(z) == list(range(n)) and all(unzigzag(zigzag(v, n), n) == v for v in range(n))
    assert zigzag(0, n) == 0 and (n < 3 or (zigzag(1, n), zigzag(-1, n)) == (1, 2))
    spans = [Magnitude(n).span(c) for c in range(len(Magnitude(n).classes.counts))]
    assert sum(count for _, count in spans) == n and [first for first, _ in spans] == sorted({f for f, _ in spans})


def test_symbols_decode_back_and_the_ledger_is_close_to_the_payload():
    rng = np.random.default_rng(1)
    values = [(int(rng.integers(0, 6)), int(min(127, rng.geometric(0.2) - 1))) for _ in range(400)]

    def run(coder, given):
        small, big, out = Adaptive.uniform(6), Magnitude(128), []
        for pair in given:
            a = coder.code(small, None if pair is None else pair[0], "a")
            b = coder.code_magnitude(big, None if pair is None else pair[1], "b")
            out.append((a, b))
        return out

    enc = Encoder()
    assert run(enc, values) == values
    payload = enc.payload()
    assert run(Decoder(payload), [None] * len(values)) == values
    ideal = sum(bits for _, bits in enc.ledger.values())
    assert ideal <= 8 * len(payload) <= ideal + 64
    assert enc.ledger["b"][1] / 400 < 7  # a geometric magnitude costs less than its 7 raw bits


def test_a_value_outside_the_model_is_refused():
    with pytest.raises(IFSError, match="outside"):
        Encoder().code(Adaptive.uniform(4), 4)
    with pytest.raises(IFSError, match="positive"):
        Adaptive(np.array([1.0, 0.0]))
