"""`ifslib.core.scoring.losses`: the multiscale pyramid, each loss's gradient against finite differences, names checked."""
import pytest
import torch

import ifslib
from ifslib.core.scoring.losses import DEFAULT_LOSS, LOSSES, check_loss
from ifslib.errors import IFSError

SIZE = 16


@pytest.fixture(scope="module")
def koch_target():
    return ifslib.load_target(ifslib.patterns.koch(depth=2), SIZE)


def test_multiscale_sums_the_pyramid():
    a, b = torch.rand(16, 16), torch.rand(16, 16)
    levels = ifslib.losses.pyramid(a, 5)
    assert [t.shape[0] for t in levels] == [16, 8, 4, 2, 1]
    assert ifslib.losses.multiscale_mse(a, b, 0) == ifslib.losses.mse(a, b)
    mn = ifslib.losses.pyramid(a, 1, "min")[1]
    assert mn[0, 0] == a[:2, :2].min()


def test_unknown_loss(koch_target):
    with pytest.raises(ValueError, match="unknown loss 'l3'; known losses: pixel, multiscale_pixel"):
        ifslib.loss(torch.zeros(SIZE, SIZE), koch_target, "l3")


def test_the_default_is_a_known_loss_and_a_function_passes():
    assert DEFAULT_LOSS in LOSSES and check_loss(DEFAULT_LOSS) == DEFAULT_LOSS
    assert check_loss(len) is len


@pytest.mark.parametrize("kind", LOSSES)
def test_each_loss_gradient_matches_finite_differences(kind, koch_target):
    torch.manual_seed(0)
    distance = (torch.rand(SIZE, SIZE, dtype=torch.float64) - 0.3) / SIZE  # plane units, some inside the figure
    distance.requires_grad_(True)
    target = koch_target

    def f(d):
        return ifslib.loss(d, target, kind).double()

    assert torch.autograd.gradcheck(f, (distance,), eps=1e-7, atol=1e-6, rtol=1e-4)


def test_every_name_is_an_entry_of_the_table():
    # names.py is the torch-free list the command line checks; the table is what the code branches on
    from ifslib.core.scoring.losses import LOSS_KINDS, loss_kind
    assert set(LOSS_KINDS) == set(LOSSES)
    assert loss_kind("multiscale_pixel").family is loss_kind("pixel").family
    with pytest.raises(IFSError, match="unknown loss"):
        loss_kind("no_such_loss")


def test_a_new_entry_brings_its_own_comparison(koch_target, monkeypatch):
    """A loss is its table entry: one that compares by mean absolute error is computed so, at one scale and over the
    pyramid, with no other code told of it."""
    from ifslib.core.scoring import losses

    l1 = lambda a, b: (a - b).abs().mean((-2, -1))  # noqa: E731
    monkeypatch.setattr(losses, "LOSSES", losses.LOSSES + ("l1", "multiscale_l1"))
    monkeypatch.setitem(losses.LOSS_KINDS, "l1", losses.LossKind(losses.PIXEL, multiscale=False, compare=l1))
    monkeypatch.setitem(losses.LOSS_KINDS, "multiscale_l1", losses.LossKind(losses.PIXEL, multiscale=True, compare=l1))
    d = ifslib.distance_field(ifslib.patterns.koch(), koch_target.mask.shape[0])
    drawn, wanted = losses.PIXEL.images(d, koch_target, None)
    torch.testing.assert_close(losses.loss(d, koch_target, "l1"), l1(drawn, wanted))
    pyramid = zip(losses.pyramid(drawn, 5), losses.pyramid(wanted, 5))
    torch.testing.assert_close(losses.loss(d, koch_target, "multiscale_l1"), sum(l1(a, b) for a, b in pyramid))
