"""`ifslib.core.fitting.result`: a fit's history written for the file and read back from a checkpoint, and the
record a saved fit keeps."""
import json

import ifslib
from ifslib.core.fitting.result import FitResult, History, Stage


def _history():
    stages = [Stage(size=32, steps=40, stopped="converged", best_loss=0.25, start=0, depth=3, loss="pixel"),
              Stage(size=64, steps=10, stopped="steps", best_loss=0.125, start=0, depth="attractor")]
    return History(step=[0, 1, 2], loss=[0.5, 0.25, 0.125], seconds=[0.0, 0.1, 0.2],
                   rollbacks=[{"step": 1, "reason": "nan"}], cost=50, strategy="pyramid", stages=stages,
                   starts_tried=1, chamfer=0.4, recovered=True)


def test_a_stage_writes_its_set_fields_in_the_files_order():
    stage = Stage(size=64, steps=10, stopped="steps", best_loss=0.5, maps=3, depth="attractor")
    assert list(stage.to_dict()) == ["maps", "size", "depth", "steps", "stopped", "best_loss"]


def test_history_round_trips_through_json_as_a_checkpoint_reads_it():
    history = _history()
    written = json.loads(json.dumps(history.to_dict()))
    assert "kind" not in written and "auto" not in written  # unset fields are left out of the file
    assert written["stages"][1] == {"start": 0, "size": 64, "depth": "attractor", "steps": 10, "stopped": "steps",
                                    "best_loss": 0.125}
    assert History.from_dict(written) == history


def test_to_dict_is_a_copy():
    history = _history()
    written = history.to_dict()
    written["loss"].append(9.0)
    written["rollbacks"][0]["step"] = 7
    assert history.loss == [0.5, 0.25, 0.125] and history.rollbacks == [{"step": 1, "reason": "nan"}]


def test_record_writes_the_history_into_both_ifs():
    koch = ifslib.patterns.koch(depth=2)
    result = FitResult(best=koch.clone(), final=koch.clone(), history=_history(), best_loss=0.125, best_step=2)
    assert result.record() is result
    assert result.best.meta["history"] == result.final.meta["history"] == _history().to_dict()
