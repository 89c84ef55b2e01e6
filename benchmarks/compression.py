"""Fractal image compression against JPEG, WebP and JPEG 2000, per image and rate, at no more bytes.

For scikit-image's six photographs as gray (``--size`` pixels a side, default 256: a square crop of
the original, resized with anti-aliasing), at each ``--bpp``: the collage coder and attractor coding
(`ifslib.compression`), the file's bytes, PSNR and SSIM of the decoded image, encode seconds (attractor:
the collage search included) and decode seconds (median of 3); then the best quality of JPEG
(Pillow, ``optimize=True``), WebP (``method=6``) and JPEG 2000 (Pillow's OpenJPEG, a rate layer) whose
file is no larger than the attractor coder's. A dash: the codec cannot get that small. Then, per image,
attractor coding at the lowest rate JPEG reaches (quality 1), decoding at 2x against bicubic
upscaling of the 1x decoding (both against the 2x crop; for a photograph under twice the size,
that reference is itself enlarged, and the table says so), and what a 512² image costs. The load
average is printed first: the cores are shared, so times are upper bounds.

    python benchmarks/compression.py [--size 256] [--bpp 0.15 0.25 0.5] [--images camera coins]
                                      [--s-bits 5 --m-bits 7] [--rates-only]
"""
from __future__ import annotations

import argparse
import io
import os
import statistics
import time

import numpy as np
import torch
from PIL import Image, features
from skimage import color, data, transform
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

from ifslib.compression import CodeOptions, RefineOptions, compress, decode, refine, to_bytes
from ifslib.compression.encode import pad
from ifslib.compression.repartition import repartition

IMAGES = ("camera", "astronaut", "coffee", "coins", "chelsea", "rocket")


def photo(name: str, size: int) -> np.ndarray:
    """scikit-image's photograph ``name`` as gray ``(size, size)`` float64 in [0, 1] (a square crop, resized)."""
    im = getattr(data, name)()
    im = color.rgb2gray(im[..., :3]) if im.ndim == 3 else im / 255.0
    side = min(im.shape)
    top, left = (im.shape[0] - side) // 2, (im.shape[1] - side) // 2
    return np.clip(transform.resize(im[top:top + side, left:left + side], (size, size), anti_aliasing=True), 0, 1)


def psnr(a, b) -> float:
    return float(peak_signal_noise_ratio(np.asarray(b, float), np.asarray(a, float), data_range=1.0))


def ssim(a, b) -> float:
    return float(structural_similarity(np.asarray(a, float), np.asarray(b, float), data_range=1.0))


def _pillow(gray: np.ndarray, fmt: str, **kw) -> tuple[int, np.ndarray]:
    buf = io.BytesIO()
    Image.fromarray((gray * 255).round().astype(np.uint8)).save(buf, fmt, **kw)
    return buf.tell(), np.asarray(Image.open(io.BytesIO(buf.getvalue())).convert("L"), dtype=float) / 255


def codec(gray: np.ndarray, name: str, quality: float) -> tuple[int, np.ndarray]:
    """``(bytes, decoded)`` of one Pillow codec at ``quality`` (JPEG2000: a compression ratio's inverse)."""
    if name == "JPEG":
        return _pillow(gray, "JPEG", quality=int(quality), optimize=True)
    if name == "WebP":
        return _pillow(gray, "WEBP", quality=int(quality), method=6)
    return _pillow(gray, "JPEG2000", quality_mode="rates", quality_layers=[100 / quality], irreversible=True)


def best_under(gray: np.ndarray, name: str, limit: int):
    """The codec's best ``(bytes, decoded)`` no larger than ``limit`` bytes, or None."""
    lo, hi = (1, 95) if name != "WebP" else (0, 100)
    best = None
    if name == "JPEG2000":
        lo, hi = 0.05, 100.0  # quality = 100 / compression ratio
        for _ in range(18):
            mid = (lo + hi) / 2
            size, out = codec(gray, name, mid)
            if size <= limit:
                best, lo = (size, out), mid
            else:
                hi = mid
        return best
    while lo <= hi:
        mid = (lo + hi) // 2
        size, out = codec(gray, name, mid)
        if size <= limit:
            best, lo = (size, out), mid + 1
        else:
            hi = mid - 1
    return best


def timed(fn, repeat: int = 1):
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return out, statistics.median(times)


def fractal(gray: np.ndarray, bpp: float, method: str, options: CodeOptions = CodeOptions()) -> dict:
    code, t_enc = timed(lambda: compress(gray, bpp=bpp, method=method, options=options))
    decoded, t_dec = timed(lambda: decode(code), 3)
    image = decoded.image.numpy()
    return {"code": code, "bytes": len(to_bytes(code)), "psnr": psnr(image, gray), "ssim": ssim(image, gray),
            "enc": t_enc, "dec": t_dec, "image": image}


def controls(gray: np.ndarray, collage_code) -> tuple[float, float]:
    """PSNR of the two halves of attractor coding alone: ``(maps refined on the collage's partition,
    the collage coder with the same rate-distortion pruning scored by the collage, no decoder)``."""
    held = refine(collage_code, gray, RefineOptions(repartitions=0))
    target = pad(torch.as_tensor(gray, dtype=torch.float32), collage_code.options)
    pruned = repartition(collage_code, target, target)
    assert pruned.bits() <= collage_code.bits()
    return psnr(decode(held).image, gray), psnr(decode(pruned).image, gray)


def cell(result) -> str:
    return "—" if result is None else f"{result[0]} B {psnr(result[1], result[2]):.2f} / {ssim(result[1], result[2]):.3f}"


def rate_table(names, rates, size, codecs, options: CodeOptions = CodeOptions()) -> list[tuple]:
    print(f"\n## {size}² gray: PSNR (dB) / SSIM at no more bytes than attractor coding"
          f" ({options.s_bits}-bit s, {options.m_bits}-bit m)\n")
    print("| image | bpp | collage | attractor | gain dB | gain, partition held | collage, RD partition | "
          + " | ".join(codecs) + " | encode s (collage / attractor) | decode s |")
    print("|" + "---|" * (9 + len(codecs)))
    rows = []
    for name in names:
        gray = photo(name, size)
        for bpp in rates:
            col, att = fractal(gray, bpp, "collage", options), fractal(gray, bpp, "attractor", options)
            held, pruned = controls(gray, col["code"])
            others = []
            for c in codecs:
                got = best_under(gray, c, att["bytes"])
                others.append(cell(None if got is None else (got[0], got[1], gray)))
            print(f"| {name} | {bpp} | {col['bytes']} B {col['psnr']:.2f} / {col['ssim']:.3f} | {att['bytes']} B "
                  f"{att['psnr']:.2f} / {att['ssim']:.3f} | {att['psnr'] - col['psnr']:+.2f} | {held - col['psnr']:+.2f} | "
                  f"{pruned:.2f} ({pruned - col['psnr']:+.2f}) | " + " | ".join(others)
                  + f" | {col['enc']:.1f} / {att['enc']:.1f} | {att['dec']:.3f} |", flush=True)
            rows.append((name, bpp, col, att, held, pruned))
    gains = [a["psnr"] - c["psnr"] for _, _, c, a, _, _ in rows]
    print(f"\nattractor - collage: mean {np.mean(gains):+.2f} dB, smallest {min(gains):+.2f} dB, "
          f"{sum(g >= 0.5 for g in gains)} of {len(gains)} cells at +0.5 dB or more")
    for label, k in (("partition held", 4), ("collage with the RD partition", 5)):
        other = [r[k] - r[2]["psnr"] for r in rows]
        print(f"{label} - collage: mean {np.mean(other):+.2f} dB, from {min(other):+.2f} to {max(other):+.2f}")
    print(f"attractor - collage with the RD partition: mean "
          f"{np.mean([r[3]['psnr'] - r[5] for r in rows]):+.2f} dB")
    print(f"attractor encode: {min(r[3]['enc'] for r in rows):.1f} to {max(r[3]['enc'] for r in rows):.1f} s; "
          f"decode {min(r[3]['dec'] for r in rows):.3f} to {max(r[3]['dec'] for r in rows):.3f} s")
    return rows


def jpeg_floor(names, size) -> None:
    print(f"\n## At the lowest rate JPEG reaches (quality 1, optimize=True), {size}²\n")
    print("| image | JPEG bytes (bpp) | JPEG PSNR / SSIM | attractor bytes | attractor PSNR / SSIM |")
    print("|---|---|---|---|---|")
    for name in names:
        gray = photo(name, size)
        size_j, out = codec(gray, "JPEG", 1)
        att = fractal(gray, 8 * size_j / gray.size, "attractor")
        print(f"| {name} | {size_j} ({8 * size_j / gray.size:.3f}) | {psnr(out, gray):.2f} / {ssim(out, gray):.3f} | "
              f"{att['bytes']} | {att['psnr']:.2f} / {att['ssim']:.3f} |", flush=True)


def zoom(names, size, bpp) -> None:
    print(f"\n## Decoding at 2x ({size}² code at {bpp} bpp) against the {2 * size}² original\n")
    print("| image | 2x reference | fractal 2x PSNR / SSIM | bicubic of 1x PSNR / SSIM | difference dB |")
    print("|---|---|---|---|---|")
    for name in names:
        gray, big = photo(name, size), photo(name, 2 * size)
        side = min(getattr(data, name)().shape[:2])
        # a photograph smaller than the 2x size is enlarged to make the reference, which then holds no
        # finer detail than the 1x image: an interpolated truth, which favours bicubic interpolation
        reference = ("the original" if side == 2 * size else
                     f"downsized from {side} px" if side > 2 * size else f"enlarged from {side} px")
        code = compress(gray, bpp=bpp)
        two = decode(code, 2).image.numpy()
        one = decode(code).image.numpy().astype(np.float32)
        cubic = np.clip(np.asarray(Image.fromarray(one, mode="F").resize((2 * size, 2 * size), Image.BICUBIC)), 0, 1)
        print(f"| {name} | {reference} | {psnr(two, big):.2f} / {ssim(two, big):.3f} | {psnr(cubic, big):.2f} / {ssim(cubic, big):.3f} "
              f"| {psnr(two, big) - psnr(cubic, big):+.2f} |", flush=True)


def large(name: str, size: int, bpp: float) -> None:
    gray = photo(name, size)
    col, att = fractal(gray, bpp, "collage"), fractal(gray, bpp, "attractor")
    print(f"\n## {name} at {size}², {bpp} bpp\n\ncollage: {col['psnr']:.2f} dB, encoded in {col['enc']:.1f} s; "
          f"attractor: {att['psnr']:.2f} dB, encoded in {att['enc']:.1f} s (collage search included); "
          f"decoded in {att['dec']:.3f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--bpp", type=float, nargs="+", default=[0.15, 0.25, 0.5])
    parser.add_argument("--images", nargs="+", default=list(IMAGES))
    parser.add_argument("--large", type=int, default=512, help="side of the one large image timed (0: none)")
    parser.add_argument("--s-bits", type=int, default=CodeOptions().s_bits, help="bits of s, both coders (rate table)")
    parser.add_argument("--m-bits", type=int, default=CodeOptions().m_bits, help="bits of m, both coders (rate table)")
    parser.add_argument("--rates-only", action="store_true", help="the rate table alone")
    args = parser.parse_args()
    options = CodeOptions(s_bits=args.s_bits, m_bits=args.m_bits)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; torch threads {torch.get_num_threads()}; "
          f"Pillow JPEG 2000: {features.check('jpg_2000')}, WebP: {features.check('webp')}")
    codecs = ["JPEG", "WebP"] + (["JPEG2000"] if features.check("jpg_2000") else [])
    rate_table(args.images, args.bpp, args.size, codecs, options)
    if args.rates_only:
        return
    jpeg_floor(args.images, args.size)
    zoom(args.images, args.size, 0.25)
    if args.large:
        large(args.images[0], args.large, 0.25)


if __name__ == "__main__":
    main()
