"""Quantization of a block's contrast s and mean gray level m to the integers the file stores."""
from __future__ import annotations

import torch

from .config import CodeOptions


def s_levels(options: CodeOptions) -> int:
    """Half the number of contrast levels: s = s_max * (index - half) / half, index in [0, 2 * half)."""
    return 2 ** (options.s_bits - 1)


def quantize_s(s: torch.Tensor, options: CodeOptions) -> torch.Tensor:
    """Contrast values ``(...)`` -> the nearest level's index ``(...)`` (int64), ``|s|`` clipped to s_max."""
    half = s_levels(options)
    return torch.clamp(torch.round(s / options.s_max * half) + half, 0, 2 * half - 1).long()


def dequantize_s(index: torch.Tensor, options: CodeOptions, dtype=torch.float32) -> torch.Tensor:
    """Level indices ``(...)`` -> contrast values ``(...)``; index ``half`` is s = 0 (a flat block)."""
    half = s_levels(options)
    return (index.to(dtype) - half) * (options.s_max / half)


def quantize_m(m: torch.Tensor, options: CodeOptions) -> torch.Tensor:
    """Mean gray levels ``(...)`` in [0, 1] -> indices ``(...)`` (int64) of ``2**m_bits`` levels."""
    top = 2**options.m_bits - 1
    return torch.clamp(torch.round(m * top), 0, top).long()


def dequantize_m(index: torch.Tensor, options: CodeOptions, dtype=torch.float32) -> torch.Tensor:
    """Level indices ``(...)`` -> mean gray levels ``(...)`` in [0, 1]."""
    return index.to(dtype) / (2**options.m_bits - 1)


def zero_s(options: CodeOptions) -> int:
    """The index of s = 0: a block stored by its mean alone, with no domain."""
    return s_levels(options)
