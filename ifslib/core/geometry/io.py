"""The ``ifslib/1`` JSON file: read, validate, write (the format: docs/guide/conventions.md)."""
from __future__ import annotations

import functools
import json
import math
import os
import tempfile
from importlib import resources
from pathlib import Path
from typing import Any

from ...errors import IFSError
from .ifs import IFS
from .shapes import SHAPES

FORMAT = "ifslib/1"
KNOWN_FORMATS = (FORMAT,)
_REQUIRED = ("format", "points", "rules", "primitives", "depth")
#: The file name of the format's JSON Schema, in this package folder (``ifslib/core/geometry``).
SCHEMA_FILE = "ifslib-1.schema.json"


@functools.lru_cache(maxsize=1)
def _schema_text() -> str:
    return resources.files(__package__).joinpath(SCHEMA_FILE).read_text(encoding="utf-8")


def schema() -> dict:
    """The JSON Schema (draft 2020-12) of the ``ifslib/1`` file, a fresh dict; the reader also checks what a schema
    cannot say (indices in range, finite numbers)."""
    return json.loads(_schema_text())


def _require(doc: dict, key: str, where: str) -> Any:
    if key not in doc:
        raise IFSError(f"{where} is missing the field {key!r}")
    return doc[key]


def _indices(value: Any, where: str) -> list[int]:
    if not isinstance(value, list) or not all(isinstance(i, int) and not isinstance(i, bool) for i in value):
        raise IFSError(f"{where} must be a list of integer point indices, got {value!r}")
    return value


def ifs_from_dict(doc: dict) -> IFS:
    """Build and validate an IFS from a parsed ``ifslib/1`` document; `IFSError` names the field at fault."""
    if not isinstance(doc, dict):
        raise IFSError(f"an IFS document must be a JSON object, got {type(doc).__name__}")
    fmt = _require(doc, "format", "the IFS document")
    if fmt not in KNOWN_FORMATS:
        raise IFSError(f"unknown format {fmt!r}; this reader knows: {', '.join(KNOWN_FORMATS)}")
    for key in _REQUIRED:
        _require(doc, key, "the IFS document")
    points = doc["points"]
    if (not isinstance(points, list) or not points
            or not all(isinstance(p, list) and len(p) == 2 and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                                      for c in p) for p in points)):
        raise IFSError("'points' must be a non-empty list of [x, y] number pairs")
    if any(not math.isfinite(c) for p in points for c in p):
        raise IFSError("'points' holds a value that is not finite (NaN or inf)")
    rules = []
    for i, rule in enumerate(_list(doc, "rules")):
        where = f"rule {i}"
        if not isinstance(rule, dict):
            raise IFSError(f"{where} must be an object with 'kind', 'from' and 'to'")
        rules.append({"kind": _require(rule, "kind", where),
                      "from": _indices(_require(rule, "from", where), f"{where} 'from'"),
                      "to": _indices(_require(rule, "to", where), f"{where} 'to'")})
    prims = []
    for i, prim in enumerate(_list(doc, "primitives")):
        where = f"primitive {i}"
        if not isinstance(prim, dict):
            raise IFSError(f"{where} must be an object with 'kind' and 'points'")
        prims.append({"kind": _require(prim, "kind", where),
                      "points": _indices(_require(prim, "points", where), f"{where} 'points'"),
                      "radius": prim.get("radius", 0.0)})
    probabilities = doc.get("probabilities")
    if probabilities is not None and (not isinstance(probabilities, list) or not all(
            isinstance(p, (int, float)) and not isinstance(p, bool) for p in probabilities)):
        raise IFSError(f"'probabilities' must be a list of numbers, one per rule, got {probabilities!r}")
    try:
        return IFS(points, rules, prims, depth=doc["depth"], name=doc.get("name", ""),
                   fixed=_indices(doc.get("fixed", []), "'fixed'"), sigma=doc.get("sigma"), meta=doc.get("meta"),
                   probabilities=probabilities)
    except IFSError:
        raise
    except (TypeError, KeyError) as exc:  # pragma: no cover - defensive
        raise IFSError(f"malformed IFS document: {exc}") from exc


def _list(doc: dict, key: str) -> list:
    value = doc[key]
    if not isinstance(value, list):
        raise IFSError(f"{key!r} must be a list, got {type(value).__name__}")
    return value


def ifs_to_dict(ifs: IFS) -> dict:
    """The ``ifslib/1`` document of an IFS (plain Python types, ready for `json.dump`)."""
    doc: dict[str, Any] = {"format": FORMAT, "name": ifs.name,
                           "points": [[float(x), float(y)] for x, y in ifs.points.detach().cpu().double().tolist()],
                           "rules": [{"kind": r.kind, "from": list(r.source), "to": list(r.target)} for r in ifs.rules],
                           "primitives": [], "depth": ifs.depth}
    for p in ifs.primitives:
        entry: dict[str, Any] = {"kind": p.kind, "points": list(p.points)}
        if p.radius or SHAPES[p.kind].radius == "required":
            entry["radius"] = p.radius
        doc["primitives"].append(entry)
    if ifs.fixed:
        doc["fixed"] = list(ifs.fixed)
    if ifs.sigma is not None:
        doc["sigma"] = ifs.sigma
    if ifs.probabilities is not None:
        doc["probabilities"] = list(ifs.probabilities)
    if ifs.meta:
        doc["meta"] = ifs.meta
    return doc


def load_ifs(source: str | os.PathLike | dict) -> IFS:
    """Read an IFS from an ``ifslib/1`` file path, a JSON text starting with ``{``, or a parsed dict."""
    if isinstance(source, dict):
        return ifs_from_dict(source)
    text = str(source)
    if not text.lstrip().startswith("{"):
        path = Path(text)
        if not path.is_file():
            raise IFSError(f"no IFS file at {str(path)!r}")
        text = path.read_text(encoding="utf-8")
        where = str(path)
    else:
        where = "the JSON text"
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise IFSError(f"{where} is not valid JSON: {exc}") from None
    return ifs_from_dict(doc)


def save_ifs(ifs: IFS, path: str | os.PathLike) -> Path:
    """Write an IFS as an ``ifslib/1`` JSON file, atomically (a crash leaves the old file intact); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(ifs_to_dict(ifs), indent=2)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
