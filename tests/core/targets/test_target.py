"""Targets from files, arrays and IFSs; the data resolver; clear errors for bad images."""
import functools
import http.server
import threading

import numpy as np
import pytest
import torch
from PIL import Image

import ifslib
from ifslib import data


def _disk_image(size=40, mode="L", value=255, dark=False):
    yy, xx = np.mgrid[:size, :size]
    fg = (yy - 12) ** 2 + (xx - 25) ** 2 < 36
    a = np.where(fg, value, 0).astype(np.uint8)
    if dark:
        a = 255 - a
    return Image.fromarray(a, mode="L").convert(mode), fg


@pytest.mark.parametrize("mode, ext", [("L", "png"), ("RGB", "jpg"), ("RGBA", "png"), ("P", "gif")])
def test_image_files_of_every_mode(tmp_path, mode, ext):
    im, fg = _disk_image(mode=mode)
    path = tmp_path / f"t.{ext}"
    im.save(path)
    t = ifslib.load_target(path, 40)
    assert t.mask.shape == (40, 40) and abs(int(t.mask.sum()) - int(fg.sum())) <= 4
    assert t.distance[t.mask].max() == 0 and t.distance.max() > 0.3
    assert t.image.dtype == torch.float32


def test_distance_transform_in_plane_units():
    a = np.zeros((10, 10))
    a[0, 0] = 1
    t = ifslib.load_target(a, 10)
    assert t.distance[0, 3].item() == pytest.approx(0.3)  # three pixels of 1/10
    assert t.distance[3, 4].item() == pytest.approx(0.5)


def test_invert_and_resize(tmp_path):
    im, fg = _disk_image(dark=True)
    path = tmp_path / "dark.png"
    im.save(path)
    light = ifslib.load_target(path, 20, invert=False)
    assert light.mask.mean() > 0.5 and not light.inverted  # taken as asked: the white background is the figure
    dark = ifslib.load_target(path, 20, invert=True)
    assert 0 < dark.mask.mean() < 0.2 and dark.mask[6, 12] and dark.inverted
    found = ifslib.load_target(path, 20)  # its border is white: the figure is the dark disk
    assert (found.mask == dark.mask).all() and found.inverted and "its border is light" in found.polarity


def test_ifs_and_tensor_sources():
    t = ifslib.load_target(ifslib.patterns.sierpinski_carpet(depth=2), 27)
    assert 0.2 < t.mask.mean() < 0.8
    u = ifslib.load_target(torch.from_numpy(t.mask.astype(np.float32)), 27)
    assert (u.mask == t.mask).all()


def test_bad_targets(tmp_path):
    with pytest.raises(ValueError, match="no image file at"):
        ifslib.load_target(tmp_path / "absent.png", 16)
    (tmp_path / "notes.png").write_text("not an image")
    with pytest.raises(ValueError, match="is not an image this library can read"):
        ifslib.load_target(tmp_path / "notes.png", 16)
    with pytest.raises(ValueError, match="uniform"):
        ifslib.load_target(np.zeros((8, 8)), 8)
    koch = ifslib.patterns.koch(depth=1)
    outside = koch.clone(koch.points.detach() + 3.0)  # drawn entirely outside the frame
    with pytest.raises(ValueError, match="no foreground pixel"):
        ifslib.load_target(outside, 8)
    with pytest.raises(ValueError, match="all foreground"):
        ifslib.load_target(ifslib.patterns.grid(2, depth=0, extent=1.2), 8)  # a box over the whole frame
    with pytest.raises(ValueError, match="cannot make a target from a list"):
        ifslib.load_target([[0, 1]], 8)


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def test_data_download_from_a_local_server(tmp_path, monkeypatch):
    served = tmp_path / "served"
    served.mkdir()
    im, _ = _disk_image()
    im.save(served / "apple.png")
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(served)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        monkeypatch.delenv("IFSLIB_DATA", raising=False)
        monkeypatch.setenv("IFSLIB_CACHE", str(tmp_path / "cache"))
        url = f"http://127.0.0.1:{server.server_address[1]}/"
        got = data.path("apple", base_url=url)
        assert got == tmp_path / "cache" / "apple.png" and got.read_bytes() == (served / "apple.png").read_bytes()
        assert data.path("apple.png", base_url="http://127.0.0.1:9/") == got  # cached: no second download
        with pytest.raises(ValueError, match="set IFSLIB_DATA to a folder"):
            data.path("flower", base_url=url)  # 404
    finally:
        server.shutdown()
    with pytest.raises(ValueError, match="unknown image 'pear'"):
        data.path("pear")


def test_data_folder_from_environment(tmp_path, monkeypatch):
    im, _ = _disk_image()
    im.save(tmp_path / "koch.png")
    monkeypatch.setenv("IFSLIB_DATA", str(tmp_path))
    assert data.path("koch") == tmp_path / "koch.png"
    assert ifslib.load_target("koch", 40).mask.any()


def test_picture_keeps_the_files_gray_levels(tmp_path):
    """An anti-aliased thin line: the mask keeps its bright core, the picture the whole line."""
    from PIL import Image

    gray = np.zeros((64, 64), dtype=np.uint8)
    gray[30, 8:56] = 200  # the line's core
    gray[29, 8:56] = gray[31, 8:56] = 80  # anti-aliased edges, below mid-range
    Image.fromarray(gray).save(tmp_path / "line.png")
    t = ifslib.load_target(tmp_path / "line.png", 64)
    assert t.mask.sum() == 48
    assert t.picture.shape == (64, 64) and t.picture.max() == 1.0
    assert np.allclose(t.picture[29, 8:56], 0.4) and (t.picture[30, 8:56] == 1).all()
    # a source without gray levels (an IFS, a mask) shows its mask
    own = ifslib.load_target(ifslib.patterns.koch(), 32)
    assert own.gray is None and (own.picture == own.mask).all()
