"""Fractal image compression against JPEG, WebP, JPEG 2000 and AVIF, per image and rate, at no more bytes.

For scikit-image's six photographs as gray (``--size`` pixels a side, default 256: a square crop of
the original, resized with anti-aliasing), at each ``--bpp``: the collage coder and attractor coding
(`ifslib.compression`, range-coded fields: file version 2), the file's bytes, PSNR and SSIM of the
decoded image, encode seconds (attractor: the collage search included), decode seconds (median of 3)
and the seconds to read the file's fields back (``from_bytes``); attractor coding with version 1's
fixed-length fields at the same rate (what the range coder brings); then the best quality of JPEG
(Pillow, ``optimize=True``), WebP (``method=6``), JPEG 2000 (Pillow's OpenJPEG, a rate layer) and
AVIF (Pillow's libavif, its default speed 6) whose file is no larger than the attractor coder's.
A dash: the codec cannot get that small. An image that is not a downsized photograph is named with how it was
made (at 512², camera and astronaut are the originals, the other four enlargements), and the summary's gaps are
printed again without the enlargements, which are smooth and flatter every coder. Then, per image,
attractor coding at the lowest rate JPEG reaches (quality 1), decoding at 2x against bicubic
upscaling of the 1x decoding (both against the 2x crop; for a photograph under twice the size,
that reference is itself enlarged, and the table says so), and what a 512² image costs. The load
average is printed first: the cores are shared, so times are upper bounds.

    python benchmarks/compression.py [--size 256] [--bpp 0.15 0.25 0.5] [--images camera coins]
                                      [--s-bits 5 --m-bits 7] [--rates-only] [--no-fixed]
                                      [--partition quadtree|hv]
"""
from __future__ import annotations

import argparse
import io
import os
import statistics
import time
from dataclasses import replace

import numpy as np
import torch
from PIL import Image, features
from skimage import color, data, transform
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

from ifslib.compression import CodeOptions, RefineOptions, compress, decode, from_bytes, refine, to_bytes
from ifslib.compression.config import PARTITIONS

IMAGES = ("camera", "astronaut", "coffee", "coins", "chelsea", "rocket")


def photo(name: str, size: int) -> np.ndarray:
    """scikit-image's photograph ``name`` as gray ``(size, size)`` float64 in [0, 1] (a square crop, resized)."""
    im = getattr(data, name)()
    im = color.rgb2gray(im[..., :3]) if im.ndim == 3 else im / 255.0
    side = min(im.shape)
    top, left = (im.shape[0] - side) // 2, (im.shape[1] - side) // 2
    return np.clip(transform.resize(im[top:top + side, left:left + side], (size, size), anti_aliasing=True), 0, 1)


def source(name: str, size: int) -> str:
    """How ``photo(name, size)`` was made: "the original", "downsized from N px" or "enlarged from N px" (the
    crop's side). An enlarged photograph holds no detail finer than its original's pixels, so every coder finds it
    easier than a true photograph of that size."""
    side = min(getattr(data, name)().shape[:2])
    return "the original" if side == size else f"downsized from {side} px" if side > size else f"enlarged from {side} px"


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
    if name == "AVIF":
        return _pillow(gray, "AVIF", quality=int(quality))
    return _pillow(gray, "JPEG2000", quality_mode="rates", quality_layers=[100 / quality], irreversible=True)


def best_under(gray: np.ndarray, name: str, limit: int):
    """The codec's best ``(bytes, decoded)`` no larger than ``limit`` bytes, or None."""
    lo, hi = (1, 95) if name == "JPEG" else (0, 100)
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


#: the decoder's post-filter weight `compress` offers (None: the coder's `config.DEBLOCK`; --deblock sets it)
DEBLOCK_WEIGHT = None


def fractal(gray: np.ndarray, bpp: float, method: str, options: CodeOptions = CodeOptions()) -> dict:
    code, t_enc = timed(lambda: compress(gray, bpp=bpp, method=method, options=options, deblock=DEBLOCK_WEIGHT))
    decoded, t_dec = timed(lambda: decode(code), 3)
    data = to_bytes(code)
    _, t_read = timed(lambda: from_bytes(data), 3)
    image = decoded.image.numpy()
    return {"code": code, "bytes": len(data), "psnr": psnr(image, gray), "ssim": ssim(image, gray),
            "enc": t_enc, "dec": t_dec, "read": t_read, "image": image}


def held(gray: np.ndarray, collage_code) -> float:
    """PSNR of attractor coding's moves (1) and (2) alone, on the collage's partition, in no more bytes."""
    return psnr(decode(refine(collage_code, gray, RefineOptions(repartitions=0))).image, gray)


def cell(result) -> str:
    return "—" if result is None else f"{result[0]} B {psnr(result[1], result[2]):.2f} / {ssim(result[1], result[2]):.3f}"


def rate_table(names, rates, size, codecs, options: CodeOptions = CodeOptions(), fixed: bool = True) -> list[tuple]:
    print(f"\n## {size}² gray, {options.partition} partition: PSNR (dB) / SSIM at no more bytes than attractor coding"
          f" ({options.s_bits}-bit s, {options.m_bits}-bit m, range-coded fields)\n")
    print("| image | bpp | collage | attractor | gain dB | gain, partition held | attractor, fixed fields | "
          + " | ".join(codecs) + " | encode s (collage / attractor) | decode s | read s |")
    print("|" + "---|" * (10 + len(codecs)))
    rows = []
    for name in names:
        gray = photo(name, size)
        made = source(name, size)
        # downsizing is the ordinary case; an original or an enlargement is named beside the image
        label = name if made.startswith("downsized") else f"{name} ({made})"
        for bpp in rates:
            col, att = fractal(gray, bpp, "collage", options), fractal(gray, bpp, "attractor", options)
            kept = held(gray, col["code"])
            v1 = fractal(gray, bpp, "attractor", replace(options, coder="fixed")) if fixed else None
            others = []
            for c in codecs:
                got = best_under(gray, c, att["bytes"])
                others.append(None if got is None else (got[0], got[1], gray))
            v1_cell = "—" if v1 is None else f"{v1['bytes']} B {v1['psnr']:.2f} ({att['psnr'] - v1['psnr']:+.2f})"
            print(f"| {label} | {bpp} | {col['bytes']} B {col['psnr']:.2f} / {col['ssim']:.3f} | {att['bytes']} B "
                  f"{att['psnr']:.2f} / {att['ssim']:.3f} | {att['psnr'] - col['psnr']:+.2f} | {kept - col['psnr']:+.2f} | "
                  f"{v1_cell} | " + " | ".join(cell(o) for o in others)
                  + f" | {col['enc']:.1f} / {att['enc']:.1f} | {att['dec']:.3f} | {att['read']:.3f} |", flush=True)
            rows.append({"name": name, "made": made, "bpp": bpp, "col": col, "att": att, "held": kept, "v1": v1,
                         "codecs": {c: (None if o is None else psnr(o[1], gray)) for c, o in zip(codecs, others)}})
    summary(rows, codecs)
    return rows


def summary(rows, codecs) -> None:
    gains = [r["att"]["psnr"] - r["col"]["psnr"] for r in rows]
    print(f"\nattractor - collage: mean {np.mean(gains):+.2f} dB, smallest {min(gains):+.2f} dB, "
          f"{sum(g >= 0.5 for g in gains)} of {len(gains)} cells at +0.5 dB or more")
    kept = [sum(r[k]["code"].options.deblock > 0 for r in rows) for k in ("att", "col")]
    print(f"post-filter kept (decoded closer with it): {kept[0]} of {len(rows)} attractor files, "
          f"{kept[1]} of {len(rows)} collage files")
    other = [r["held"] - r["col"]["psnr"] for r in rows]
    print(f"partition held - collage: mean {np.mean(other):+.2f} dB, from {min(other):+.2f} to {max(other):+.2f}")
    if rows[0]["v1"] is not None:
        coder = [r["att"]["psnr"] - r["v1"]["psnr"] for r in rows]
        print(f"range-coded - fixed fields (attractor): mean {np.mean(coder):+.2f} dB, from {min(coder):+.2f} "
              f"to {max(coder):+.2f}")
    codec_gaps(rows, codecs)
    print(f"attractor encode: {min(r['att']['enc'] for r in rows):.1f} to {max(r['att']['enc'] for r in rows):.1f} s "
          f"(collage {min(r['col']['enc'] for r in rows):.1f} to {max(r['col']['enc'] for r in rows):.1f} s); "
          f"decode {min(r['att']['dec'] for r in rows):.3f} to {max(r['att']['dec'] for r in rows):.3f} s; "
          f"read {min(r['att']['read'] for r in rows):.3f} to {max(r['att']['read'] for r in rows):.3f} s")
    true = [r for r in rows if not r["made"].startswith("enlarged")]
    if 0 < len(true) < len(rows):
        # enlargements are smooth at this size and flatter every coder: the gaps on true photographs alone
        names = ", ".join(dict.fromkeys(r["name"] for r in true))
        gains = [r["att"]["psnr"] - r["col"]["psnr"] for r in true]
        print(f"\nnot enlarged ({names}): attractor - collage mean {np.mean(gains):+.2f} dB, "
              f"smallest {min(gains):+.2f} dB")
        codec_gaps(true, codecs)


def codec_gaps(rows, codecs) -> None:
    for bpp in sorted({r["bpp"] for r in rows}):
        at = [r for r in rows if r["bpp"] == bpp]
        gaps = []
        for c in codecs:
            d = [r["att"]["psnr"] - r["codecs"][c] for r in at if r["codecs"][c] is not None]
            gaps.append(f"{c} {np.mean(d):+.2f} dB ({len(d)} of {len(at)} reach it, ahead in "
                        f"{sum(x > 0 for x in d)})" if d else f"{c} —")
        print(f"at {bpp} bpp, attractor - codec, mean: " + "; ".join(gaps))


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
        # a photograph smaller than the 2x size is enlarged to make the reference, which then holds no
        # finer detail than the 1x image: an interpolated truth, which favours bicubic interpolation
        reference = source(name, 2 * size)
        code = compress(gray, bpp=bpp, deblock=DEBLOCK_WEIGHT)
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
    parser.add_argument("--no-fixed", action="store_true", help="skip the fixed-length fields' column")
    parser.add_argument("--partition", choices=PARTITIONS, default="quadtree",
                        help="the fractal coders' partition (hv: no fixed-field column, version 1 holds quadtrees only)")
    parser.add_argument("--deblock", type=float, default=None,
                        help="the decoder's post-filter weight the coders offer (default: config.DEBLOCK; 0: none, "
                             "the coder before the filter)")
    args = parser.parse_args()
    global DEBLOCK_WEIGHT
    DEBLOCK_WEIGHT = args.deblock
    if args.deblock is not None:
        print(f"post-filter weight offered: {args.deblock:g}")
    options = CodeOptions(s_bits=args.s_bits, m_bits=args.m_bits, partition=args.partition)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; torch threads {torch.get_num_threads()}; "
          f"Pillow JPEG 2000: {features.check('jpg_2000')}, WebP: {features.check('webp')}, "
          f"AVIF: {features.check('avif')}")
    codecs = ["JPEG", "WebP"] + [c for c, f in (("JPEG2000", "jpg_2000"), ("AVIF", "avif")) if features.check(f)]
    rate_table(args.images, args.bpp, args.size, codecs, options, not args.no_fixed and args.partition == "quadtree")
    if args.rates_only:
        return
    jpeg_floor(args.images, args.size)
    zoom(args.images, args.size, 0.25)
    if args.large:
        large(args.images[0], args.large, 0.25)


if __name__ == "__main__":
    main()
