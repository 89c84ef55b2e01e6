"""The JSON Schema of the ifslib/1 file: every file the library writes is valid under it, and it
refuses what the reader refuses wherever a schema can say so (docs/guide/conventions.md)."""
import copy
import inspect
import json
import re
from pathlib import Path

import jsonschema  # declared in the dev extra: a missing one fails, never skips
import pytest
import torch

import ifslib
from ifslib.automatic import auto
from ifslib.core.geometry import io, patterns, random_fractals

from conftest import mixed, sheared_mixed

ROOT = Path(__file__).resolve().parents[3]
PAGE = ROOT / "docs" / "guide" / "conventions.md"


@pytest.fixture(scope="module")
def validator():
    schema = io.schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _saved(ifs, tmp_path, name="f.json"):
    """The document of ``ifs`` as `save_ifs` writes it, read back as plain JSON."""
    return json.loads(ifslib.save_ifs(ifs, tmp_path / name).read_text(encoding="utf-8"))


#: Every pattern of ifslib.patterns, built with its defaults or the smallest arguments it needs.
PATTERNS = {
    "koch": lambda: patterns.koch(),
    "koch_thick": lambda: patterns.koch(radius=0.01),
    "koch_unit": lambda: patterns.koch_unit(),
    "koch_paper": lambda: patterns.koch_paper(),
    "koch_like": lambda: patterns.koch_like([[-0.4, 0.0], [0.0, 0.3], [0.4, 0.0]]),
    "grid": lambda: patterns.grid(3),
    "sierpinski_carpet": lambda: patterns.sierpinski_carpet(),
    "rosette": lambda: patterns.rosette(),
    "affine": lambda: patterns.affine([[[0.5, 0.1, 0.0], [0.0, 0.4, 0.1]]], primitive="segment"),
    "fern": lambda: patterns.fern(),
    "sierpinski_triangle": lambda: patterns.sierpinski_triangle(),
    "random_ifs": lambda: random_fractals.random_ifs(3),
    "by_name": lambda: patterns.by_name("rosette5"),
}


def test_every_pattern_function_is_covered():
    builders = {name for name, f in inspect.getmembers(patterns, inspect.isfunction)
                if f.__module__ == patterns.__name__ and not name.startswith("_")
                and inspect.signature(f).return_annotation in ("IFS", ifslib.IFS)}
    assert builders <= set(PATTERNS), f"add to PATTERNS: {sorted(builders - set(PATTERNS))}"


@pytest.mark.parametrize("name", sorted(PATTERNS))
def test_saved_patterns_are_valid(name, validator, tmp_path):
    validator.validate(_saved(PATTERNS[name](), tmp_path))


@pytest.mark.parametrize("name", sorted(patterns.PATTERNS))
def test_named_patterns_are_valid(name, validator, tmp_path):
    validator.validate(_saved(patterns.by_name(name), tmp_path))


def test_every_field_and_kind_is_valid(validator, tmp_path):
    """Disks with their radius, boxes, thick segments, affine rules, fixed points and sigma."""
    for ifs in (mixed(), sheared_mixed()):
        ifs.sigma, ifs.fixed = 0.004, (0, 1)
        doc = _saved(ifs, tmp_path)
        assert {"sigma", "fixed"} <= set(doc) and {p["kind"] for p in doc["primitives"]} == {"segment", "box", "disk"}
        validator.validate(doc)


def test_a_fitted_file_is_valid(validator, tmp_path):
    """A fit's result: meta with its history (and a checkpoint's state), an automatic start's pattern."""
    target = ifslib.load_target(patterns.koch(depth=2), 32)
    result = ifslib.fit(patterns.koch(depth=2), target, steps=3, progress=False, strategy="plain",
                        checkpoint=ifslib.Checkpoint(tmp_path / "checkpoint.json", every=2))
    fitted = result.best
    fitted.meta["target"] = {"polarity": target.polarity, "inverted": target.inverted}
    fitted.meta["scores"] = {"depth": {"depth": 2, "iou": 0.5, "f1": 0.6, "chamfer": 0.7},
                             "attractor": {"iou": 0.5, "f1": 0.6, "chamfer": 0.7}}
    doc = _saved(fitted, tmp_path)
    assert {"history", "target", "scores"} <= set(doc["meta"]) and doc["meta"]["history"]["loss"]
    validator.validate(doc)
    checkpoint = json.loads((tmp_path / "checkpoint.json").read_text(encoding="utf-8"))
    assert "fit" in checkpoint["meta"]
    validator.validate(checkpoint)
    shape = auto.shape_start(ifslib.load_target(patterns.sierpinski_carpet(depth=2), 32), 4)
    doc = _saved(shape, tmp_path)
    assert doc["meta"]["pattern"]["kind"] == "shape"
    validator.validate(doc)


def test_the_pages_example_is_valid_and_loads(validator):
    """The example file on the conventions page is a valid file, and the one the page describes."""
    blocks = re.findall(r"```json\n(.*?)```", PAGE.read_text(encoding="utf-8"), flags=re.S)
    assert blocks, f"no ```json block in {PAGE}"
    doc = json.loads(blocks[0])
    validator.validate(doc)
    ifs = ifslib.load_ifs(doc)
    assert ifs.n_leaves() == 4 ** doc["depth"] * len(doc["primitives"])


def _doc(**change):
    doc = {"format": "ifslib/1", "name": "two", "points": [[-0.4, 0], [0, 0.2], [0.4, 0], [0.0, -0.2]],
           "rules": [{"kind": "segment", "from": [0, 2], "to": [0, 1]}, {"kind": "segment", "from": [0, 2], "to": [1, 2]}],
           "primitives": [{"kind": "segment", "points": [0, 2]}], "depth": 2}
    doc.update(copy.deepcopy(change))
    return doc


def _without(field):
    doc = _doc()
    del doc[field]
    return doc


def _rule(**change):
    return _doc(rules=[{"kind": "segment", "from": [0, 2], "to": [0, 1], **change}])


def _primitive(**change):
    return _doc(primitives=[{"kind": "segment", "points": [0, 2], **change}])


#: Documents that load_ifs refuses and that the schema can refuse too.
REFUSED = {
    "not an object": [_doc()],
    "wrong format": _doc(format="ifslib/9"),
    "format not a string": _doc(format=1),
    "no format": _without("format"),
    "no points": _without("points"),
    "no rules": _without("rules"),
    "no primitives": _without("primitives"),
    "no depth": _without("depth"),
    "points empty": _doc(points=[]),
    "points not a list": _doc(points={"0": [0, 0]}),
    "a point of three numbers": _doc(points=[[0, 0, 0], [1, 0], [0, 1], [1, 1]]),
    "a point of one number": _doc(points=[[0], [1, 0], [0, 1], [1, 1]]),
    "a coordinate as text": _doc(points=[["0", 0], [1, 0], [0, 1], [1, 1]]),
    "a coordinate as a boolean": _doc(points=[[True, 0], [1, 0], [0, 1], [1, 1]]),
    "rules empty": _doc(rules=[]),
    "rules not a list": _doc(rules={"kind": "segment", "from": [0, 2], "to": [0, 1]}),
    "a rule not an object": _doc(rules=[[0, 2, 0, 1]]),
    "bad rule kind": _rule(kind="spiral"),
    "a rule without kind": _doc(rules=[{"from": [0, 2], "to": [0, 1]}]),
    "a rule without from": _doc(rules=[{"kind": "segment", "to": [0, 1]}]),
    "a rule without to": _doc(rules=[{"kind": "segment", "from": [0, 2]}]),
    "a segment rule of three points": _rule(to=[0, 1, 2]),
    "a square rule of one point": _rule(kind="square", **{"from": [0]}),
    "an affine rule of two points": _rule(kind="affine", **{"from": [0, 1], "to": [1, 2]}),
    "a negative index": _rule(to=[-1, 1]),
    "a fractional index": _rule(to=[0.5, 1]),
    "an index as text": _rule(to=["0", 1]),
    "an index as a boolean": _rule(to=[False, 1]),
    "primitives empty": _doc(primitives=[]),
    "a primitive not an object": _doc(primitives=[[0, 2]]),
    "bad primitive kind": _primitive(kind="star"),
    "a primitive without points": _doc(primitives=[{"kind": "segment"}]),
    "a segment primitive of one point": _primitive(points=[0]),
    "a box of three points": _primitive(kind="box", points=[0, 1, 2]),
    "a disk of two points": _primitive(kind="disk", points=[0, 1], radius=0.1),
    "a disk without radius": _primitive(kind="disk", points=[3]),
    "a disk of radius 0": _primitive(kind="disk", points=[3], radius=0),
    "a negative radius": _primitive(radius=-0.1),
    "depth negative": _doc(depth=-1),
    "depth fractional": _doc(depth=1.5),
    "depth as text": _doc(depth="3"),
    "depth as a boolean": _doc(depth=True),
    "fixed not a list": _doc(fixed=0),
    "fixed negative": _doc(fixed=[-1]),
    "fixed fractional": _doc(fixed=[0.5]),
    "sigma zero": _doc(sigma=0),
    "sigma negative": _doc(sigma=-0.01),
    "sigma too large": _doc(sigma=1e4),
    "probabilities not a list": _doc(probabilities=0.5),
    "probabilities empty": _doc(probabilities=[]),
    "a probability of zero": _doc(probabilities=[0, 1]),
    "a negative probability": _doc(probabilities=[-0.5, 1.5]),
    "a probability as text": _doc(probabilities=["0.5", 0.5]),
    "a probability as a boolean": _doc(probabilities=[True, 0.5]),
}


def test_the_base_document_is_valid(validator):
    validator.validate(_doc())
    ifslib.load_ifs(_doc())


def _load_file(doc, tmp_path):
    """load_ifs on ``doc`` written as a file (Python's json writes NaN as the token NaN, which it reads back)."""
    path = tmp_path / "doc.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    return ifslib.load_ifs(path)


@pytest.mark.parametrize("case", sorted(REFUSED))
def test_refused_by_both(case, validator, tmp_path):
    doc = REFUSED[case]
    with pytest.raises(ifslib.IFSError):
        _load_file(doc, tmp_path)
    assert not validator.is_valid(doc), f"the schema accepts a document that load_ifs refuses: {case}"


#: What the reader refuses and no schema can say (it depends on the points' number, on a JSON
#: number's spelling, or on non-finite values that JSON itself has no words for): the schema
#: accepts these, the reader does not. If one becomes expressible, move it to REFUSED.
BEYOND_A_SCHEMA = {
    "a rule's index past the points": _rule(to=[0, 4]),
    "a primitive's index past the points": _primitive(points=[0, 4]),
    "a fixed index past the points": _doc(fixed=[4]),
    "depth written 2.0": _doc(depth=2.0),
    "an index written 1.0": _rule(to=[0, 1.0]),
    "a coordinate that is not finite": _doc(points=[[float("nan"), 0], [1, 0], [0, 1], [1, 1]]),
    "probabilities that do not sum to 1": _doc(probabilities=[0.3, 0.3]),
    "fewer probabilities than rules": _doc(probabilities=[1.0]),
    "a probability that is not finite": _doc(probabilities=[float("nan"), 0.5]),
}


@pytest.mark.parametrize("case", sorted(BEYOND_A_SCHEMA))
def test_refused_by_the_reader_only(case, validator, tmp_path):
    doc = BEYOND_A_SCHEMA[case]
    with pytest.raises(ifslib.IFSError):
        _load_file(doc, tmp_path)
    assert validator.is_valid(doc)


def test_the_schema_is_shipped_beside_the_reader():
    path = Path(io.__file__).with_name(io.SCHEMA_FILE)
    assert path.is_file()
    assert io.schema() == json.loads(path.read_text(encoding="utf-8"))
    first = io.schema()
    first["properties"].clear()
    assert io.schema()["properties"], "schema() must return a fresh copy"
    assert io.schema()["properties"]["format"]["const"] == io.FORMAT


def test_the_schema_knows_the_library_kinds():
    """The kinds the schema lists are those the library builds."""
    from ifslib.core.geometry.primitives import PRIMITIVE_KINDS
    from ifslib.core.geometry.rules import RULE_KINDS, RULE_POINTS

    defs = io.schema()["$defs"]
    assert defs["rule"]["properties"]["kind"]["enum"] == list(RULE_KINDS)
    # the table of shapes (one module a kind) and the schema name the same kinds
    assert sorted(defs["primitive"]["properties"]["kind"]["enum"]) == sorted(PRIMITIVE_KINDS)
    for kind, need in RULE_POINTS.items():
        for other in range(1, 5):
            doc = _rule(kind=kind, **{"from": list(range(other)), "to": list(range(other))})
            assert jsonschema.Draft202012Validator(io.schema()).is_valid(doc) == (other == need), (kind, other)
    # each kind's points and radius as its entry in the table of shapes says (the schema is written by hand)
    from ifslib.core.geometry.shapes import SHAPES

    valid = jsonschema.Draft202012Validator(io.schema()).is_valid
    for kind, shape in SHAPES.items():
        for other in range(1, 5):
            assert valid(_primitive(kind=kind, points=list(range(other)), radius=0.1)) == (other == shape.points), kind
        assert valid(_primitive(kind=kind, points=list(range(shape.points)))) == (shape.radius != "required"), kind


def test_no_pointer_to_the_old_file():
    """The contract is docs/guide/conventions.md; nothing in the repository points elsewhere."""
    old = re.compile(r"\b" + "CONVEN" + "TIONS" + r"\b")  # the file outside the repository, CONVEN...TIONS.md
    paths = [ROOT / "README.md"] + [path for folder in ("ifslib", "docs", "notebooks", "tests", "benchmarks")
                                    for path in (ROOT / folder).rglob("*")
                                    if path.suffix in (".py", ".md", ".ipynb", ".json", ".txt", ".cfg", ".yaml")]
    found = [str(path.relative_to(ROOT)) for path in paths
             if path.is_file() and old.search(path.read_text(encoding="utf-8", errors="replace"))]
    assert not found, f"these files still point to the old conventions file: {found}"


def test_torch_points_round_trip_as_plain_numbers(validator, tmp_path):
    """float64 points are written as JSON numbers (no tensors, no NaN): the schema's 'number'."""
    ifs = patterns.koch().to(torch.float64)
    doc = _saved(ifs, tmp_path)
    assert all(isinstance(c, float) for p in doc["points"] for c in p)
    validator.validate(doc)
