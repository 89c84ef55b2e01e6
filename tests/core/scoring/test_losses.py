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
        loss_kind("soft_iou")
