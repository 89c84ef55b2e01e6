"""The ``auto`` strategy's choice between kinds: a plan with a rival is fitted both ways and the fit whose
attractor scores least (1 - IoU plus a cost a map) is kept, with the decision recorded."""
import pytest

import ifslib
from ifslib.automatic import auto
from ifslib.automatic.plan import Plan
from ifslib.automatic.config import AUTO

KIND_MAP_COST = AUTO.fit.kind_map_cost


def _fractal_plan(ifs, iou=0.8):
    from ifslib.automatic.fractal import Row

    row = Row(len(ifs.rules), 1.0, 0.5, 0.5, iou, 1 - iou + AUTO.search.map_cost * len(ifs.rules))
    ifs.meta["pattern"] = {"name": "auto", "kind": "fractal", "maps": len(ifs.rules), "depth": ifs.depth,
                           "search": [row.written()], "ambiguous": "the test's reason"}
    return Plan(ifs, (ifs,), "fractal", dict(ifs.meta["pattern"]), search=(row,), why="the test's reason")


def _shape_plan(target, maps=4):
    start = auto.candidates(target, [(maps, 2)], kind="shape")[0]
    return Plan(start, (start,), "shape", dict(start.meta["pattern"]))


def _fit_both(fractal, target):
    plan = _fractal_plan(fractal)
    plan = Plan(plan.start, plan.candidates, plan.kind, plan.pattern, rivals=(_shape_plan(target),), search=plan.search,
                why=plan.why)
    return ifslib.fit(plan, target, steps=20, progress=False)


@pytest.mark.slow
def test_a_fractal_is_kept_over_a_shape_when_its_attractor_draws_the_figure():
    truth = ifslib.random_fractals.random_ifs(3, 1)
    target = ifslib.load_target(ifslib.render(truth, 64, method="chaos", points=200_000, seed=1).numpy(), 64)
    result = _fit_both(truth, target)
    rows = result.history.auto.kinds
    assert [r.kind for r in rows] == ["fractal", "shape"] and [r.maps for r in rows] == [3, 4]
    assert result.history.auto.decision.startswith("the test's reason; fractal kept")
    assert result.best.meta["pattern"]["kind"] == "fractal" and "decision" in result.best.meta["pattern"]
    iou = ifslib.evaluate(result.best, target, depth="attractor")["iou"]
    assert abs(rows[0].score - (1 - iou + KIND_MAP_COST * 3)) < 1e-6  # the score is of the kept fit's attractor
    assert rows[0].score < rows[1].score
    assert result.history.cost == rows[0].steps + rows[1].steps  # both fits' steps are counted
    written = result.history.to_dict()["auto"]  # the file's copy, written from the record
    assert written["kinds"] == [r.written() for r in rows] and written["decision"] == result.history.auto.decision
    assert written["candidates"] == [{"maps": 3, "depth": truth.depth, "by": "score", "value": 1 - 0.8 + AUTO.search.map_cost * 3,
                                      "steps": 0, "seconds": 0.0}]


@pytest.mark.slow
def test_a_shape_is_kept_when_the_fractal_draws_the_figure_worse():
    from ifslib.core.targets import silhouettes

    target = ifslib.load_target(silhouettes.blob(64, seed=1).astype(float), 64)
    poor = ifslib.patterns.affine([[[0.3, 0, -0.2], [0, 0.3, 0]], [[0.3, 0, 0.2], [0, 0.3, 0]]], depth=3, name="auto")
    result = _fit_both(poor, target)
    rows = result.history.auto.kinds
    assert result.history.auto.decision.startswith("the test's reason; shape kept")
    assert result.best.meta["pattern"]["kind"] == "shape" and len(result.best.rules) == 4
    assert rows[1].score < rows[0].score and rows[1].attractor_iou > rows[0].attractor_iou


def test_a_fractal_fit_never_returns_an_attractor_worse_than_its_start(monkeypatch):
    from ifslib.automatic import fit_plan as automatic
    from ifslib.core.fitting.result import FitResult, History, Stage

    truth = ifslib.random_fractals.random_ifs(3, 1)
    target = ifslib.load_target(ifslib.render(truth, 64, method="chaos", points=200_000, seed=1).numpy(), 64)
    worse = truth.clone(truth.points.detach() * 0.8)  # every map's copy shrunk towards the centre

    def stage_to(ifs):
        def stage(frame, start, options, label, *, steps=None, max_leaves=None):
            history = History(step=[0], loss=[0.5], seconds=[0.0], stopped="steps", cost=1)
            return (FitResult(ifs.clone(), ifs.clone(), history, 0.1, 0),
                    Stage(size=64, steps=1, stopped="steps", best_loss=0.1, depth="attractor"))
        return stage

    monkeypatch.setattr(automatic, "attractor_stage", stage_to(worse))
    kept = ifslib.fit(_fractal_plan(truth.clone(), iou=0.99), target, steps=5, progress=False)
    assert ifslib.evaluate(worse, target, depth="attractor")["iou"] < ifslib.evaluate(truth, target, depth="attractor")["iou"]
    assert kept.best.points.detach().equal(truth.points.detach()) and kept.best_loss == 0.5 and kept.best_step == 0
    assert "below the start's" in kept.history.stages[0].kept_start
    assert kept.best.meta["history"]["stages"][0]["kept_start"] == kept.history.stages[0].kept_start
    monkeypatch.setattr(automatic, "attractor_stage", stage_to(truth))  # a stage no worse: its fit is returned
    fitted = ifslib.fit(_fractal_plan(worse.clone(), iou=0.5), target, steps=5, progress=False)
    assert fitted.best.points.detach().equal(truth.points.detach()) and fitted.history.stages[0].kept_start is None


@pytest.mark.slow
def test_a_fractal_that_falls_short_is_polished_by_the_splat_fit_and_the_better_attractor_kept(monkeypatch):
    import dataclasses

    from ifslib.automatic import fit_plan as automatic
    from ifslib.core.fitting.result import FitResult, History, Stage
    from ifslib.splatting import fit as splat

    truth = ifslib.random_fractals.random_ifs(3, 1)
    target = ifslib.load_target(ifslib.render(truth, 64, method="chaos", points=200_000, seed=1).numpy(), 64)
    moved = truth.clone(truth.points.detach() + 0.04)  # every copy off its place: the attractor falls short
    before = ifslib.evaluate(moved, target, depth="attractor")["iou"]
    assert before < automatic.FIT.splat_below

    def unmoved(frame, start, options, label, *, steps=None, max_leaves=None):  # a stage that leaves the maps
        history = History(step=[0], loss=[0.5], seconds=[0.0], stopped="steps", cost=1)
        return (FitResult(start.clone(), start.clone(), history, 0.5, 0),
                Stage(size=64, steps=1, stopped="steps", best_loss=0.5, depth="attractor"))

    monkeypatch.setattr(automatic, "attractor_stage", unmoved)
    polished = ifslib.fit(_fractal_plan(moved.clone(), iou=before), target, steps=150, progress=False)
    stage = polished.history.stages[-1]
    after = ifslib.evaluate(polished.best, target, depth="attractor")["iou"]
    assert stage.method == "splat" and stage.steps == 150 and stage.kept_start is None
    assert after > before + 0.05 and len(polished.best.rules) == 3
    assert polished.history.cost == 1 + 150 and len(polished.history.stages) == 2
    assert polished.best.meta["history"]["stages"][-1]["method"] == "splat"

    # a polish that draws worse is not kept, and the stage says why
    worse = truth.clone(truth.points.detach() * 0.5)
    worse.probabilities = (0.2, 0.3, 0.5)
    real = splat.fit_splat
    monkeypatch.setattr(splat, "fit_splat", lambda image, start=None, options=None:
                        dataclasses.replace(real(image, start=start, options=options), ifs=worse))
    kept = ifslib.fit(_fractal_plan(moved.clone(), iou=before), target, steps=5, progress=False)
    assert kept.best.points.detach().equal(moved.points.detach())
    assert "the stage's maps kept" in kept.history.stages[-1].kept_start

    # splat_below 0 turns the polish off
    monkeypatch.setattr(automatic, "FIT", dataclasses.replace(automatic.FIT, splat_below=0.0))
    plain = ifslib.fit(_fractal_plan(moved.clone(), iou=before), target, steps=5, progress=False)
    assert [s.method for s in plain.history.stages] != [] and all(s.method != "splat" for s in plain.history.stages)


def test_the_kind_is_chosen_on_full_precision_scores_and_written_rounded():
    from ifslib.automatic.fit_plan import choose_kind
    from ifslib.automatic.choice import AutoRun, Kind
    from ifslib.core.fitting.frame import Frame

    target = ifslib.load_target(ifslib.render(ifslib.random_fractals.random_ifs(3, 1), 32, method="chaos", points=50_000,
                                              seed=1).numpy(), 32)
    results = []
    for kind, maps in (("fractal", 3), ("shape", 4)):
        result = ifslib.fit(ifslib.random_fractals.random_ifs(maps, 2), target, steps=0, strategy="plain", progress=False)
        result.history.kind, result.history.auto = kind, AutoRun(kind, maps, (), {"kind": kind})
        for ifs in (result.best, result.final):
            ifs.meta["pattern"] = {"kind": kind}
        results.append(result)
    # the shape's score is 4e-5 below the fractal's: equal to 4 digits, where the fewer maps won
    fractal_iou, shape_iou = 0.9, 0.9 + KIND_MAP_COST + 4e-5
    rows = (Kind("fractal", 3, fractal_iou, 0), Kind("shape", 4, shape_iou, 0))
    assert rows[1].score < rows[0].score and rows[0].written()["score"] == rows[1].written()["score"]
    kept = choose_kind(results, Frame(target, 0, 0, progress=False), ious=[fractal_iou, shape_iou])
    assert kept.best.meta["pattern"]["kind"] == "shape" and "shape kept" in kept.history.auto.decision
    assert [r.attractor_iou for r in kept.history.auto.kinds] == [fractal_iou, shape_iou]  # full precision kept
    assert [r["attractor_iou"] for r in kept.history.to_dict()["auto"]["kinds"]] == [round(fractal_iou, 4),
                                                                                       round(shape_iou, 4)]
