"""`ifslib.fit`: each loss fits, and a fit is reproducible, resumable and NaN-safe; snapshots and animations."""
import pytest
import torch

import ifslib

from common_testing import KOCH_DEPTH as DEPTH, KOCH_SIZE as SIZE, koch_start as _start


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=DEPTH), SIZE)


@pytest.mark.parametrize("kind", ifslib.LOSSES)
def test_each_loss_decreases_on_a_koch_target(koch_target, kind):
    r = ifslib.fit(_start(koch_target), koch_target, steps=15, lr=0.01, loss=kind, progress=False, strategy="plain")
    assert r.best_loss < 0.8 * r.history.loss[0]


def test_seeded_fit_is_reproducible(koch_target):
    runs = [ifslib.fit(_start(koch_target, 3), koch_target, steps=8, progress=False, strategy="plain") for _ in range(2)]
    assert runs[0].history.loss == runs[1].history.loss
    assert torch.equal(runs[0].final.points, runs[1].final.points)


def test_keep_every_snapshots_and_gif_animation(tmp_path):
    from PIL import Image

    from ifslib.teaching.animate import GAP

    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 24)
    start = ifslib.initialize(ifslib.patterns.koch(depth=2), target, jitter=0.03, seed=1)
    plain = ifslib.fit(start, target, steps=12, progress=False, strategy="plain")
    kept = ifslib.fit(start, target, steps=12, progress=False, options=ifslib.RunOptions(keep_every=5), strategy="plain")
    assert plain.history.snapshots is None and "snapshots" not in plain.best.meta["history"]
    assert kept.history.snapshots["step"] == [0, 5, 10, 12]
    assert torch.equal(kept.best.points, plain.best.points)  # keeping snapshots changes nothing
    assert kept.history.snapshots["points"][0] == start.points.detach().tolist()
    path = ifslib.animate(kept.history, target, tmp_path / "fit.gif", progress=False)
    saved = ifslib.load_ifs(ifslib.save_ifs(kept.best, tmp_path / "kept.json"))
    assert ifslib.animate(saved.meta["history"], target, tmp_path / "saved.gif", progress=False).exists()
    with Image.open(path) as gif:
        assert gif.n_frames == 4
        assert gif.size == (3 * 24 + 2 * GAP, 24)


def test_animate_needs_snapshots_and_a_known_format(tmp_path):
    target = ifslib.load_target(ifslib.patterns.koch(depth=1), 16)
    result = ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=2, progress=False, options=ifslib.RunOptions(keep_every=1), strategy="plain")
    with pytest.raises(ifslib.IFSError, match="keep_every"):
        ifslib.animate(ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=1, progress=False, strategy="plain").history,
                       target, tmp_path / "a.gif")
    with pytest.raises(ifslib.IFSError, match=r"\.gif or \.mp4"):
        ifslib.animate(result.history, target, tmp_path / "a.png")
    with pytest.raises(ifslib.IFSError, match="keep_every"):
        ifslib.RunOptions(keep_every=0)


def test_animate_mp4_without_ffmpeg_says_so(tmp_path, monkeypatch):
    import importlib

    animate_module = importlib.import_module("ifslib.teaching.animate")  # the module, not the function of that name
    target = ifslib.load_target(ifslib.patterns.koch(depth=1), 16)
    result = ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=2, progress=False, options=ifslib.RunOptions(keep_every=1), strategy="plain")
    monkeypatch.setattr(animate_module.shutil, "which", lambda name: None)
    with pytest.raises(ifslib.IFSError, match="ffmpeg"):
        ifslib.animate(result.history, target, tmp_path / "fit.mp4", progress=False)
