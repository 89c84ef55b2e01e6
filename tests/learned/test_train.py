"""A tiny training run: seeded, its loss falls, its weights round-trip through the file the guess loads."""
import numpy as np
import pytest
import torch

from ifslib.errors import IFSError
from ifslib.learned import train as training
from ifslib.learned.estimator import load_network

TINY = training.Training(steps=30, pool=64, validation=16, batch=16, width=8, curve_every=15, lr=3e-3,
                         progress=False)


@pytest.fixture(scope="module")
def tiny():
    return training.train(TINY)


def test_the_loss_falls_and_the_curve_is_kept(tiny):
    network, curve = tiny
    assert [step for step, *_ in curve] == [15, 30]
    assert all(np.isfinite(row).all() for row in curve)
    assert curve[-1][1] < curve[0][1]


def test_the_same_seed_gives_the_same_weights(tiny):
    again, _ = training.train(TINY)
    assert all(torch.equal(a, b) for a, b in zip(tiny[0].state_dict().values(), again.state_dict().values()))


def test_weights_round_trip_through_the_file(tiny, tmp_path, monkeypatch):
    path = tmp_path / "guess.pt"
    training.save(tiny[0], path)
    state = torch.load(path, weights_only=True)
    assert state["shape"] == {"size": 64, "grid": 16, "width": 8}
    picture = torch.rand(1, 1, 64, 64)
    want = tiny[0](picture)
    from ifslib.learned import estimator as guess_module
    monkeypatch.setattr(guess_module.resources, "files", lambda package: tmp_path)
    load_network.cache_clear()
    try:
        got = load_network()(picture)
    finally:
        load_network.cache_clear()
    assert torch.allclose(got[0], want[0], atol=2e-2) and torch.allclose(got[1], want[1], atol=2e-2)


@pytest.mark.parametrize("bad, message", [({"steps": 0}, "steps"), ({"pool": 2.5}, "pool"), ({"lr": 0}, "lr"),
                                          ({"lr": float("nan")}, "lr"), ({"progress": "yes"}, "progress")])
def test_bad_options_are_refused(bad, message):
    with pytest.raises(IFSError, match=message):
        training.Training(**bad)


def test_the_command_refuses_bad_options_in_words(capsys):
    with pytest.raises(SystemExit) as exit:
        training.main(["--steps", "0", "--out", "unused.pt"])
    assert exit.value.code == 2 and "steps" in capsys.readouterr().err
