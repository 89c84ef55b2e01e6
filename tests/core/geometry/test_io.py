"""The ifslib/1 JSON file: round trips and clear errors for bad documents."""
import json

import pytest
import torch

import ifslib

from conftest import mixed


@pytest.mark.parametrize("make", [ifslib.patterns.koch, ifslib.patterns.sierpinski_carpet, lambda: ifslib.patterns.grid(4),
                                  lambda: mixed(depth=3)])
def test_round_trip(tmp_path, make):
    ifs = make()
    ifs.sigma, ifs.meta, ifs.fixed = 0.004, {"history": {"loss": [1.0, 0.5]}}, (0,)
    path = ifslib.save_ifs(ifs, tmp_path / "sub" / "f.json")
    back = ifslib.load_ifs(path)
    torch.testing.assert_close(back.points.detach().double(), ifs.points.detach().double())
    assert (back.rules, back.primitives, back.depth, back.sigma, back.meta, back.fixed) == \
        (ifs.rules, ifs.primitives, ifs.depth, ifs.sigma, ifs.meta, ifs.fixed)
    assert back.points.requires_grad and back.points.is_leaf
    torch.testing.assert_close(ifslib.render(back, 16).double(), ifslib.render(ifs, 16).double(), rtol=0, atol=1e-5)
    assert ifslib.load_ifs(json.loads(path.read_text())).rules == ifs.rules  # dicts are accepted too
    assert ifslib.load_ifs(path.read_text()).depth == ifs.depth  # and JSON text


def test_convention_example_loads():
    doc = {"format": "ifslib/1", "name": "koch",
           "points": [[-0.4, 0.0], [-0.1333, 0.0], [0.0, 0.2309], [0.1333, 0.0], [0.4, 0.0]],
           "rules": [{"kind": "segment", "from": [0, 4], "to": [i, i + 1]} for i in range(4)],
           "primitives": [{"kind": "segment", "points": [0, 4]}], "depth": 3}
    ifs = ifslib.load_ifs(doc)
    assert ifs.n_leaves() == 64 and ifs.name == "koch"


def _doc(**change):
    doc = {"format": "ifslib/1", "points": [[-0.4, 0], [0, 0.2], [0.4, 0]],
           "rules": [{"kind": "segment", "from": [0, 2], "to": [0, 1]}, {"kind": "segment", "from": [0, 2], "to": [1, 2]}],
           "primitives": [{"kind": "segment", "points": [0, 2]}], "depth": 2}
    doc.update(change)
    return doc


@pytest.mark.parametrize("change, message", [
    ({"format": "ifslib/9"}, r"unknown format 'ifslib/9'; this reader knows: ifslib/1"),
    ({"points": [[0, 0], [float("nan"), 1]]}, r"not finite"),
    ({"points": [[0, 0, 0]]}, r"'points' must be a non-empty list of \[x, y\] number pairs"),
    ({"rules": [{"kind": "segment", "from": [0, 7], "to": [0, 1]}]}, r"rule 0 uses point index 7, out of range for 3 points"),
    ({"rules": [{"kind": "spiral", "from": [0, 2], "to": [0, 1]}]}, r"unknown rule kind 'spiral'; known kinds: segment, square"),
    ({"rules": [{"kind": "segment", "to": [0, 1]}]}, r"rule 0 is missing the field 'from'"),
    ({"primitives": [{"kind": "disk", "points": [0]}]}, r"a disk primitive needs a radius > 0"),
    ({"primitives": [{"kind": "segment", "points": [0, 9]}]}, r"primitive 0 uses point index 9, out of range"),
    ({"depth": -2}, r"depth must be an integer >= 0, got -2"),
    ({"depth": 1.5}, r"depth must be an integer >= 0"),
])
def test_bad_documents(change, message):
    with pytest.raises(ValueError, match=message):
        ifslib.load_ifs(_doc(**change))


@pytest.mark.parametrize("field", ["format", "points", "rules", "primitives", "depth"])
def test_missing_field(field):
    doc = _doc()
    del doc[field]
    with pytest.raises(ValueError, match=f"missing the field '{field}'"):
        ifslib.load_ifs(doc)


def test_zero_length_rule_segment_in_a_file():
    doc = _doc(points=[[0.1, 0.1], [0, 0.2], [0.1, 0.1]])
    ifs = ifslib.load_ifs(doc)  # loads: the points may still move
    with pytest.raises(ValueError, match="its source segment from point 0 to point 2 has zero length"):
        ifslib.render(ifs, 8)


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(ValueError, match="no IFS file at"):
        ifslib.load_ifs(tmp_path / "absent.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ValueError, match="is not valid JSON"):
        ifslib.load_ifs(bad)


def test_probabilities_round_trip(tmp_path):
    fern = ifslib.patterns.fern()
    fern.probabilities = (0.01, 0.85, 0.07, 0.07)
    back = ifslib.load_ifs(ifslib.save_ifs(fern, tmp_path / "fern.json"))
    assert back.probabilities == (0.01, 0.85, 0.07, 0.07)
    torch.testing.assert_close(back.measure_probabilities(), torch.tensor([0.01, 0.85, 0.07, 0.07], dtype=torch.float64))


def test_a_file_without_probabilities_reads_as_before(tmp_path):
    """An old file has no probabilities: none are written back, and the default (|det|, with a floor) is used."""
    ifs = ifslib.load_ifs(_doc())
    assert ifs.probabilities is None and "probabilities" not in ifslib.core.geometry.io.ifs_to_dict(ifs)
    torch.testing.assert_close(ifs.measure_probabilities(), torch.tensor([0.5, 0.5], dtype=torch.float64))


@pytest.mark.parametrize("probabilities, message", [
    ([0.5], r"2 rules but 1 probabilities"),
    ([0.5, 0.6], r"sum to 1, they sum to 1\.1; divide each by their sum"),
    ([0.0, 1.0], r"rule\(s\) \[0\] is not a finite number > 0"),
    ([float("nan"), 1.0], r"rule\(s\) \[0\] is not a finite number > 0"),
    ([-0.5, 1.5], r"rule\(s\) \[0\] is not a finite number > 0"),
    (["a", 1.0], r"'probabilities' must be a list of numbers"),
    (0.5, r"'probabilities' must be a list of numbers"),
])
def test_bad_probabilities(probabilities, message):
    with pytest.raises(ifslib.IFSError, match=message):
        ifslib.load_ifs(_doc(probabilities=probabilities))


def test_probabilities_checked_on_the_object():
    with pytest.raises(ifslib.IFSError, match="4 rules but 3 probabilities"):
        ifslib.IFS(ifslib.patterns.koch().points, ifslib.patterns.koch().rules, ifslib.patterns.koch().primitives,
                   probabilities=[0.2, 0.3, 0.5])
    with pytest.raises(ifslib.IFSError, match="not booleans"):
        ifslib.IFS([[0, 0], [1, 0]], [{"kind": "segment", "from": [0, 1], "to": [0, 0]}],
                   [{"kind": "segment", "points": [0, 1]}], probabilities=[True])


def test_probabilities_checked_when_set():
    fern = ifslib.patterns.fern()
    with pytest.raises(ifslib.IFSError, match="sum to 1"):
        fern.probabilities = (0.5, 0.5, 0.5, 0.5)
    fern.probabilities = [0.01, 0.85, 0.07, 0.07]
    assert fern.probabilities == (0.01, 0.85, 0.07, 0.07) and fern.clone().probabilities == fern.probabilities
    fern.probabilities = None
    assert fern.probabilities is None
