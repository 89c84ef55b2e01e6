"""Images as people have them: which part is the figure (the border rule, alpha), and every kind of file.

Each kind of image is written with Pillow into ``tmp_path`` from one figure and must give the mask of
the white-on-black file, bit for bit (within a few pixels for JPEG); the command line says which
part it took and how to take the other.
"""
from __future__ import annotations

import json
import os
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageDraw

import ifslib
from ifslib.cli import main
from ifslib.core.targets import image as targets
from ifslib.core.targets.target import resize_target

SIZE = 64


def _figure(n: int = 128) -> np.ndarray:
    """A white figure on black, ``(n, n)`` uint8: a triangle and a disk, off-centre, clear of the border."""
    im = Image.new("L", (n, n), 0)
    draw = ImageDraw.Draw(im)
    draw.polygon([(0.12 * n, 0.85 * n), (0.62 * n, 0.85 * n), (0.37 * n, 0.2 * n)], fill=255)
    draw.ellipse([0.6 * n, 0.15 * n, 0.85 * n, 0.4 * n], fill=255)
    return np.asarray(im)


def _rgba(alpha: np.ndarray, colour=(0, 0, 0)) -> Image.Image:
    out = np.zeros(alpha.shape + (4,), np.uint8)
    out[..., :3] = colour
    out[..., 3] = alpha
    return Image.fromarray(out, "RGBA")


def _palette_with_transparency(fig: np.ndarray) -> Image.Image:
    im = Image.fromarray(fig).convert("P")
    im.info["transparency"] = 0  # the black entry: the background is transparent
    return im


# name -> (file name, image made from the white-on-black figure, what Target.polarity says)
KINDS = {
    "white on black": ("wob.png", lambda f: Image.fromarray(f), "its border is dark"),
    "black on white": ("bow.png", lambda f: Image.fromarray(255 - f), "its border is light"),
    "black on white, RGB": ("bow_rgb.png", lambda f: Image.fromarray(np.dstack([255 - f] * 3)), "its border is light"),
    "black on transparent": ("bot.png", lambda f: _rgba(f), "alpha channel"),
    "white on transparent": ("wot.png", lambda f: _rgba(f, (255, 255, 255)), "alpha channel"),
    "red on transparent": ("rot.png", lambda f: _rgba(f, (200, 0, 0)), "alpha channel"),
    # opaque everywhere: read by its colours, as RGB
    "black on white, opaque RGBA": ("bow_rgba.png", lambda f: Image.fromarray(np.dstack([255 - f] * 3 + [np.full_like(f, 255)]),
                                                                             "RGBA"), "its border is light"),
    "black on transparent, LA": ("bot_la.png", lambda f: Image.fromarray(np.dstack([np.zeros_like(f), f]), "LA"),
                                 "alpha channel"),
    "1-bit, black on white": ("bow_1.png", lambda f: Image.fromarray(255 - f).convert("1", dither=Image.NONE),
                              "its border is light"),
    "palette, black on white": ("bow_p.gif", lambda f: Image.fromarray(255 - f).convert("P"), "its border is light"),
    "palette with transparency": ("p_t.png", _palette_with_transparency, "alpha channel"),
    "16-bit, black on white": ("bow_16.png", lambda f: Image.fromarray((255 - f).astype(np.uint16) * 257),
                               "its border is light"),
    # every value above 255: Pillow's conversion to 8 bits would clip the whole image to white
    "16-bit, narrow range": ("wob_16n.png", lambda f: Image.fromarray(f.astype(np.uint16) * 4 + 30000),
                             "its border is dark"),
}


@pytest.fixture(scope="module")
def figure():
    return _figure()


@pytest.fixture(scope="module")
def reference(figure, tmp_path_factory):
    path = tmp_path_factory.mktemp("ref") / "wob.png"
    Image.fromarray(figure).save(path)
    return ifslib.load_target(path, SIZE)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_kind_gives_the_white_on_black_mask(kind, figure, reference, tmp_path):
    name, make, said = KINDS[kind]
    path = tmp_path / name
    make(figure).save(path)
    target = ifslib.load_target(path, SIZE)
    assert said in target.polarity, target.polarity
    assert target.inverted == ("its border is light" in said)
    assert (target.mask == reference.mask).all(), f"{kind}: {int((target.mask != reference.mask).sum())} pixels differ"


@pytest.mark.parametrize("invert", [False, True])
def test_jpeg_noise_moves_a_few_pixels(invert, figure, reference, tmp_path):
    path = tmp_path / "figure.jpg"
    Image.fromarray(255 - figure if invert else figure).convert("RGB").save(path, quality=75)
    target = ifslib.load_target(path, SIZE)
    assert target.inverted is invert
    differ = int((target.mask != reference.mask).sum())
    assert differ <= 0.02 * reference.mask.sum(), differ


def test_the_paper_images_keep_their_masks():
    """All four have a black border: found as white on black, the same mask as invert=False."""
    folder = os.environ.get("IFSLIB_DATA")
    if not folder or not (Path(folder) / "koch.png").is_file():
        pytest.skip("the paper's images are not in IFSLIB_DATA")
    for name in ("koch", "sierpinski", "apple", "flower"):
        for size in (64, 256):
            found, given = ifslib.load_target(name, size), ifslib.load_target(name, size, invert=False)
            assert not found.inverted and "its border is dark: 100 %" in found.polarity
            assert (found.mask == given.mask).all() and (found.gray == given.gray).all()


def _touching(n: int, share: float) -> np.ndarray:
    """White on black: a block over the left columns, as wide as makes about ``share`` of the border band light."""
    band = targets.border_band((n, n))
    for width in range(1, n):
        a = np.zeros((n, n), np.uint8)
        a[:, :width] = 255
        if (a[band] > 0).mean() >= share:
            return a
    raise AssertionError(share)


@pytest.mark.parametrize("share, dark", [(0.3, False), (0.45, None), (0.55, None), (0.8, True)])
def test_a_figure_touching_the_border(share, dark, tmp_path):
    """Under 40 % of the border light: light figure; over 60 %: dark figure; between: the paper's way, said a guess."""
    a = _touching(128, share)
    assert abs((a[targets.border_band(a.shape)] > 0).mean() - share) < 0.03  # the drawing does what it says
    path = tmp_path / "touch.png"
    Image.fromarray(a).save(path)
    target = ifslib.load_target(path, SIZE)
    if dark is None:
        assert not target.inverted and "a guess: its border is split" in target.polarity, target.polarity
    else:
        assert target.inverted is dark, target.polarity
    assert target.polarity.startswith("a dark figure" if dark else "a light figure")


def test_the_alpha_of_a_card_with_transparent_corners_is_not_the_figure(figure, reference, tmp_path):
    """Opaque at its border (rounded corners): the colours decide, the transparent corners read as white."""
    dark = np.dstack([255 - figure] * 3 + [np.full_like(figure, 255)])
    dark[:6, :6, 3] = dark[:6, -6:, 3] = dark[-6:, :6, 3] = dark[-6:, -6:, 3] = 0
    dark[:6, :6, :3] = 0  # what a transparent pixel stores does not matter
    path = tmp_path / "card.png"
    Image.fromarray(dark, "RGBA").save(path)
    target = ifslib.load_target(path, SIZE)
    assert target.inverted and "its border is light" in target.polarity
    assert (target.mask == reference.mask).all()


def test_exif_orientation_is_applied(figure, reference, tmp_path):
    exif = Image.Exif()
    exif[0x0112] = 3  # rotated 180 degrees: the viewer turns it back
    path = tmp_path / "turned.png"
    Image.fromarray(np.rot90(figure, 2).copy()).save(path, exif=exif)
    assert (ifslib.load_target(path, SIZE).mask == reference.mask).all()


def test_invert_overrides_the_rule(figure, reference, tmp_path):
    path = tmp_path / "bow.png"
    Image.fromarray(255 - figure).save(path)
    background = ifslib.load_target(path, SIZE, invert=False)
    # the complement but for the pixels at exactly mid-range, which are figure both ways
    assert (background.mask == ~reference.mask).mean() > 0.98 and background.mask.mean() > 0.5
    assert background.polarity == "the light part, as asked (invert=False)" and not background.inverted
    assert ifslib.load_target(path, SIZE, invert=True).polarity == "the dark part, as asked (invert=True)"
    transparent = tmp_path / "bot.png"
    _rgba(figure).save(transparent)
    hole = ifslib.load_target(transparent, SIZE, invert=True)
    assert (hole.mask == ~reference.mask).mean() > 0.98 and hole.polarity == "the transparent part, as asked (invert=True)"
    with pytest.raises(ifslib.IFSError, match="invert must be True"):
        ifslib.load_target(path, SIZE, invert="yes")


def test_arrays_and_ifss_are_taken_as_they_are(figure):
    light_border = (255 - figure).astype(float)
    target = ifslib.load_target(light_border, SIZE)  # an array's figure is where it is high: no guess
    assert not target.inverted and target.mask.mean() > 0.5 and "array is high" in target.polarity
    carpet = ifslib.load_target(ifslib.patterns.sierpinski_carpet(depth=2), 27)
    assert carpet.polarity == "the IFS's drawing"
    assert resize_target(target, 32).polarity == target.polarity  # the pyramid keeps it


def test_a_large_image_is_reduced_as_it_is_read(figure, reference, tmp_path):
    """4096² pixels: read as 2048² at most, so numpy never holds the whole image in float64 (128 MiB a copy)."""
    path = tmp_path / "large.png"
    Image.fromarray(255 - figure).resize((4096, 4096), Image.NEAREST).save(path)
    tracemalloc.start()
    try:
        target = ifslib.load_target(path, SIZE)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 128 * 2**20, f"{peak / 2**20:.0f} MiB traced"
    assert target.inverted and int((target.mask != reference.mask).sum()) <= 0.02 * reference.mask.sum()


def test_unreadable_images_end_in_one_line(tmp_path, capsys, monkeypatch):
    cases = {"uniform.png": (Image.new("L", (40, 40), 200), "uniform"),
             "clear.png": (Image.new("RGBA", (40, 40), (0, 0, 0, 0)), "uniform"),
             "lab.tif": (Image.new("LAB", (40, 40)), "not an image this library can read")}
    for name, (im, said) in cases.items():
        im.save(tmp_path / name)
        assert main(["fit", str(tmp_path / name), "--size", "16", "--steps", "1", "-o", str(tmp_path / "o.json")]) == 2
        err = capsys.readouterr().err
        assert said in err and "Traceback" not in err and err.count("error:") == 1, err
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 100)  # 40x40 is then over twice Pillow's limit
    with pytest.raises(ifslib.IFSError, match="too large to read safely"):
        ifslib.load_target(tmp_path / "uniform.png", 16)


def _fit(path: Path, tmp_path: Path, capsys, *options: str) -> tuple[str, dict]:
    out = tmp_path / "fit.json"
    assert main(["fit", str(path), "--size", "16", "--steps", "1", "--strategy", "plain", *options,
                 "-o", str(out)]) == 0
    err = capsys.readouterr().err
    return err, json.loads(out.read_text())["meta"]["target"]


def test_the_command_line_says_which_part_it_took(figure, tmp_path, capsys):
    cases = [(Image.fromarray(figure), (), "target: a light figure on a dark background (its border is dark: 100 % of it); "
              "--invert to fit the other part", False),
             (Image.fromarray(255 - figure), (), "target: a dark figure on a light background (its border is light: "
              "100 % of it); --no-invert to fit the other part", True),
             (_rgba(figure), (), "target: an opaque figure on a transparent background (its alpha channel); "
              "--invert to fit the other part", False),
             (Image.fromarray(255 - figure), ("--no-invert",), "target: the light part, as asked (invert=False); "
              "--invert to fit the other part", False),
             (Image.fromarray(figure), ("--invert",), "target: the dark part, as asked (invert=True); "
              "--no-invert to fit the other part", True)]
    for i, (im, options, line, inverted) in enumerate(cases):
        path = tmp_path / f"case{i}.png"
        im.save(path)
        err, meta = _fit(path, tmp_path, capsys, *options)
        assert err.splitlines()[0] == line, err
        assert meta == {"polarity": line[len("target: "):line.index(";")], "inverted": inverted}


def test_a_split_border_is_said_a_guess_and_quiet_says_nothing(tmp_path, capsys):
    path = tmp_path / "split.png"
    Image.fromarray(_touching(128, 0.5)).save(path)  # half its border light
    err, meta = _fit(path, tmp_path, capsys)
    assert err.startswith("target: a light figure on a dark background, a guess: its border is split (50 % light)"), err
    assert "--invert to fit the other part" in err.splitlines()[0] and meta["inverted"] is False
    err, meta = _fit(path, tmp_path, capsys, "--quiet")
    assert err == "" and "a guess" in meta["polarity"]  # the file still records it
