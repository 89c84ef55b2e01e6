"""`ifslib.automatic.choice`: the automatic fit's record decides at full precision and writes one row layout."""
import json

from ifslib.automatic.config import AUTO
from ifslib.automatic.choice import AutoRun, Candidate, Kind
from ifslib.core.fitting.result import History


def test_every_candidate_is_written_in_one_layout_whatever_it_was_compared_by():
    probe = Candidate(8, 3, "loss", 1.23456789e-5, 150, 0.5)
    searched = Candidate(3, 3, "score", 0.1234567, 0, 2.0)
    assert probe.written().keys() == searched.written().keys() == {"maps", "depth", "by", "value", "steps", "seconds"}
    assert probe.written()["value"] == 1.23456789e-5  # not rounded: the file keeps what decided


def test_the_file_is_written_from_the_record_once_and_meta_leaves_out_the_search_table():
    pattern = {"name": "auto", "kind": "fractal", "maps": 3, "search": [{"maps": 3, "iou": 0.9}], "rule": "mdl"}
    kinds = (Kind("fractal", 3, 0.9, 10), Kind("shape", 24, 0.93, 20))
    run = AutoRun("fractal", 3, (Candidate(3, 3, "score", 0.22, 0, 1.0),), pattern, kinds, "fractal kept")
    written = json.loads(json.dumps(History(auto=run).to_dict()))["auto"]  # through JSON, as the file holds it
    assert written["search"] == pattern["search"] and written["chosen"] == 3 and written["decision"] == "fractal kept"
    assert written["kinds"] == [k.written() for k in kinds] and written["candidates"][0]["by"] == "score"
    assert run.described() == {"name": "auto", "kind": "fractal", "maps": 3, "rule": "mdl", "chosen": 3,
                               "decision": "fractal kept"}
    assert "auto" not in History.from_dict(History(auto=run).to_dict()).to_dict()  # a checkpoint has no record


def test_a_kind_scores_one_minus_its_iou_plus_the_price_of_its_maps():
    kind = Kind("shape", 24, 0.95, 0)
    assert kind.score == 1 - 0.95 + AUTO.fit.kind_map_cost * 24
    assert kind.written()["score"] == round(kind.score, 4)
