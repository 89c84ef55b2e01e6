"""Quantization of s and m: bounds, zero, round trips and the nearest level."""
import pytest
import torch

from ifslib.compression.config import CodeOptions
from ifslib.compression.quantize import dequantize_m, dequantize_s, quantize_m, quantize_s, zero_s


@pytest.mark.parametrize("bits", [2, 5, 8])
def test_s_levels_round_trip_and_stay_below_the_bound(bits):
    o = CodeOptions(s_bits=bits)
    index = torch.arange(2**bits)
    s = dequantize_s(index, o, torch.float64)
    assert torch.equal(quantize_s(s, o), index)
    assert s.abs().max() <= o.s_max + 1e-12
    assert dequantize_s(torch.tensor(zero_s(o)), o) == 0


def test_s_is_clipped_and_rounded_to_the_nearest_level():
    o = CodeOptions()
    s = torch.linspace(-3, 3, 1001, dtype=torch.float64)
    q = dequantize_s(quantize_s(s, o), o, torch.float64)
    levels = dequantize_s(torch.arange(2**o.s_bits), o, torch.float64)
    nearest = levels[(s.clamp(-o.s_max, o.s_max)[:, None] - levels).abs().argmin(1)]
    torch.testing.assert_close(q, nearest)


def test_m_levels_cover_zero_to_one_within_half_a_step():
    o = CodeOptions(m_bits=7)
    m = torch.rand(1000, dtype=torch.float64)
    q = dequantize_m(quantize_m(m, o), o, torch.float64)
    assert (q - m).abs().max() <= 0.5 / 127 + 1e-12
    assert dequantize_m(torch.tensor([0, 127]), o).tolist() == [0.0, 1.0]
