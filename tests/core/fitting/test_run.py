"""`ifslib.core.fitting.run`: one Adam run is resumable from a checkpoint, rolls back a NaN or non-contractive step at
half the learning rate, and never moves fixed points."""
import json
import math

import pytest
import torch

import ifslib

from common_testing import KOCH_DEPTH as DEPTH, KOCH_SIZE as SIZE, koch_start as _start


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=DEPTH), SIZE)


def test_resume_equals_uninterrupted(koch_target, tmp_path):
    start = _start(koch_target, 4)
    whole = ifslib.fit(start, koch_target, steps=12, lr=0.01, progress=False, strategy="plain")
    ckpt = tmp_path / "ckpt.json"
    ifslib.fit(start, koch_target, steps=7, lr=0.01, progress=False, checkpoint=ifslib.Checkpoint(ckpt, every=7), strategy="plain")
    assert json.loads(ckpt.read_text())["meta"]["fit"]["next_step"] == 7
    resumed = ifslib.fit(start, koch_target, steps=12, lr=0.01, progress=False, checkpoint=ifslib.Checkpoint(resume=ckpt),
                         strategy="plain")
    assert resumed.history.loss == whole.history.loss
    assert torch.equal(resumed.final.points, whole.final.points)
    assert torch.equal(resumed.best.points, whole.best.points)
    with pytest.raises(ValueError, match="is not a fit checkpoint"):
        path = ifslib.save_ifs(start, tmp_path / "plain.json")
        ifslib.fit(start, koch_target, steps=3, progress=False, checkpoint=ifslib.Checkpoint(resume=path), strategy="plain")


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
