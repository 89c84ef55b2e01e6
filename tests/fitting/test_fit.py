"""`ifslib.fit`: each loss fits, and a fit is reproducible, resumable and NaN-safe; snapshots and animations."""
import json
import math

import pytest
import torch

import ifslib

SIZE, DEPTH = 48, 2


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=DEPTH), SIZE)


def _start(target, seed=0):
    return ifslib.initialize(ifslib.patterns.koch(depth=DEPTH), target, jitter=0.05, seed=seed)


@pytest.mark.parametrize("kind", ifslib.LOSSES)
def test_each_loss_decreases_on_a_koch_target(koch_target, kind):
    r = ifslib.fit(_start(koch_target), koch_target, steps=15, lr=0.01, loss=kind, progress=False, strategy="plain")
    assert r.best_loss < 0.8 * r.history.loss[0]


def test_seeded_fit_is_reproducible(koch_target):
    runs = [ifslib.fit(_start(koch_target, 3), koch_target, steps=8, progress=False, strategy="plain") for _ in range(2)]
    assert runs[0].history.loss == runs[1].history.loss
    assert torch.equal(runs[0].final.points, runs[1].final.points)


def test_resume_equals_uninterrupted(koch_target, tmp_path):
    start = _start(koch_target, 4)
    whole = ifslib.fit(start, koch_target, steps=12, lr=0.01, progress=False, strategy="plain")
    ckpt = tmp_path / "ckpt.json"
    ifslib.fit(start, koch_target, steps=7, lr=0.01, progress=False, checkpoint=ckpt, checkpoint_every=7, strategy="plain")
    assert json.loads(ckpt.read_text())["meta"]["fit"]["next_step"] == 7
    resumed = ifslib.fit(start, koch_target, steps=12, lr=0.01, progress=False, resume=ckpt, strategy="plain")
    assert resumed.history.loss == whole.history.loss
    assert torch.equal(resumed.final.points, whole.final.points)
    assert torch.equal(resumed.best.points, whole.best.points)
    with pytest.raises(ValueError, match="is not a fit checkpoint"):
        path = ifslib.save_ifs(start, tmp_path / "plain.json")
        ifslib.fit(start, koch_target, steps=3, progress=False, resume=path, strategy="plain")


def test_nan_loss_is_rolled_back(koch_target):
    calls = []

    def flaky(distance, target):
        calls.append(1)
        value = ifslib.loss(distance, target, "distance")
        return value * math.nan if len(calls) == 4 else value

    r = ifslib.fit(_start(koch_target), koch_target, steps=10, lr=0.01, loss=flaky, progress=False, strategy="plain")
    assert [rb["step"] for rb in r.history.rollbacks] == [3]
    assert "loss is nan" in r.history.rollbacks[0]["reason"] and r.history.rollbacks[0]["lr"] == 0.005
    assert torch.isfinite(r.final.points).all() and len(r.history.loss) == 9


def test_non_contractive_step_is_rolled_back(koch_target):
    ifs = _start(koch_target)

    def blow_up(step, loss, work):
        if step == 2:
            with torch.no_grad():
                work.points[2] += 5.0  # makes rules 1 and 2 expand
    r = ifslib.fit(ifs, koch_target, steps=6, progress=False, callback=blow_up, strategy="plain")
    assert r.history.rollbacks and "not contractive" in r.history.rollbacks[0]["reason"]
    assert ifslib.IFS(r.final.points, ifs.rules, ifs.primitives).scales().max() < 1


def test_fixed_points_do_not_move(koch_target):
    ifs = _start(koch_target)
    ifs.fixed = (0, 4)
    r = ifslib.fit(ifs, koch_target, steps=5, lr=0.01, progress=False, strategy="plain")
    assert torch.equal(r.final.points[[0, 4]], ifs.points[[0, 4]])
    assert not torch.equal(r.final.points[2], ifs.points[2])


def test_keep_every_snapshots_and_gif_animation(tmp_path):
    from PIL import Image

    from ifslib.teaching.animate import GAP

    target = ifslib.load_target(ifslib.patterns.koch(depth=2), 24)
    start = ifslib.initialize(ifslib.patterns.koch(depth=2), target, jitter=0.03, seed=1)
    plain = ifslib.fit(start, target, steps=12, progress=False, strategy="plain")
    kept = ifslib.fit(start, target, steps=12, progress=False, keep_every=5, strategy="plain")
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
    result = ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=2, progress=False, keep_every=1, strategy="plain")
    with pytest.raises(ifslib.IFSError, match="keep_every"):
        ifslib.animate(ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=1, progress=False, strategy="plain").history,
                       target, tmp_path / "a.gif")
    with pytest.raises(ifslib.IFSError, match=r"\.gif or \.mp4"):
        ifslib.animate(result.history, target, tmp_path / "a.png")
    with pytest.raises(ifslib.IFSError, match="keep_every"):
        ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=1, keep_every=0)


def test_animate_mp4_without_ffmpeg_says_so(tmp_path, monkeypatch):
    import importlib

    animate_module = importlib.import_module("ifslib.teaching.animate")  # the module, not the function of that name
    target = ifslib.load_target(ifslib.patterns.koch(depth=1), 16)
    result = ifslib.fit(ifslib.patterns.koch(depth=1), target, steps=2, progress=False, keep_every=1, strategy="plain")
    monkeypatch.setattr(animate_module.shutil, "which", lambda name: None)
    with pytest.raises(ifslib.IFSError, match="ffmpeg"):
        ifslib.animate(result.history, target, tmp_path / "fit.mp4", progress=False)
