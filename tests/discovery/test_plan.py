"""The plan: which figures are fitted both as a fractal and as a shape (`ambiguous`), and the
silhouettes with thin parts that make a solid figure look porous."""
import numpy as np
import pytest

import ifslib
from ifslib.discovery import auto, plan
from ifslib.targets import silhouettes


def _pattern(maps: int, iou: float) -> dict:
    """What a fractal search records, reduced to what `ambiguous` reads: the chosen row among others."""
    return {"maps": maps, "search": [{"maps": 2, "iou": 0.99}, {"maps": maps, "iou": iou}]}


def test_a_thin_limbed_creature_looks_porous_but_a_blob_does_not():
    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    blob = ifslib.load_target(silhouettes.blob(128, seed=2).astype(float), 128)
    assert auto.classify(creature) == "shape"
    assert plan.AMBIGUOUS_SHARE <= auto.interior_share(creature) < auto.POROUS_SHARE <= auto.interior_share(blob)
    assert len(silhouettes.thin_gallery(32)) == 6


def test_ambiguous_reads_the_chosen_row_and_the_figure_share():
    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    why = plan.ambiguous(auto.interior_share(creature), _pattern(5, 0.85))
    assert why is not None and "IoU 0.850" in why and "fitted as a fractal and as a shape" in why
    # the chosen row is the one of the chosen number of maps, not the best row of the table
    assert plan.ambiguous(auto.interior_share(creature), _pattern(5, plan.CLEAR_FRACTAL_IOU)) is None
    lace = ifslib.load_target(ifslib.render(ifslib.patterns.random_ifs(3, 1), 128, method="chaos",
                                            points=200_000, seed=1).numpy(), 128)
    assert auto.interior_share(lace) < plan.AMBIGUOUS_SHARE
    # a lace is a fractal however poorly it was found
    assert plan.ambiguous(auto.interior_share(lace), _pattern(3, 0.5)) is None


@pytest.mark.parametrize("kwargs, message", [({"limbs": -1}, "limbs must be an integer >= 0"),
                                             ({"holes": 1.5}, "holes must be an integer >= 0"),
                                             ({"width": 0.0}, "width must be a number between 0 and 0.5"),
                                             ({"width": True}, "width must be a number")])
def test_limbed_refuses_bad_drawings(kwargs, message):
    with pytest.raises(ValueError, match=message):
        silhouettes.limbed(32, **kwargs)


def test_limbed_draws_its_parts():
    from scipy import ndimage

    bare = silhouettes.limbed(96, seed=0, limbs=0, tail=False, holes=0)
    full = silhouettes.limbed(96, seed=0, limbs=4, tail=True, holes=1)
    assert ndimage.label(bare)[1] == 1 and not (ndimage.binary_fill_holes(bare) & ~bare).any()
    assert (ndimage.binary_fill_holes(full) & ~full).sum() > 10  # the hole stays a hole
    assert full.sum() > bare.sum() - 200  # the limbs and the tail add more than the hole takes
    assert np.array_equal(full, silhouettes.limbed(96, seed=0, limbs=4, tail=True, holes=1))


def test_a_figure_that_may_be_a_shape_is_searched_once(monkeypatch):
    from ifslib.discovery import fractal

    configs = []

    def no_fractal(target, maps, depth, seed, *, config):
        configs.append(config)
        return None, {"search": [], "rule": "", "verdict": "none"}

    monkeypatch.setattr(plan, "fractal_start", no_fractal)
    creature = ifslib.load_target(silhouettes.limbed(128, seed=2, width=0.03).astype(float), 128)
    lace = ifslib.load_target(ifslib.render(ifslib.patterns.random_ifs(3, 1), 128, method="chaos",
                                            points=200_000, seed=1).numpy(), 128)
    assert plan.discover(creature, maps=4, depth=2).kind == "shape"
    assert plan.discover(lace, maps=4, depth=2).kind == "shape"
    assert configs == [plan.AMBIGUOUS_SEARCH, fractal.DEFAULT] and plan.AMBIGUOUS_SEARCH.again == 0
