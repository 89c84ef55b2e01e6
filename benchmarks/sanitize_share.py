"""How many of the numbers the stored notebooks print survive ``make test-stored``'s sanitize rules.

``python benchmarks/sanitize_share.py [notebooks/nbval-sanitize.cfg] [NOTEBOOK ...]``

The text outputs of every stored notebook (streams, and the ``text/plain`` of displayed results)
are read; the numbers in them counted (a run of digits with its decimals, thousands separators and
exponent: ``0.65``, ``12,922``, ``8.00e-06``); the sanitize file's rules applied as nbval applies
them (``re.sub`` of each ``regex:`` by its ``replace:``, in order); the numbers counted again. A
number a rule replaces is gone from the comparison; the share kept is the second count over the
first (the rules' replacements hold no digits, so nothing is counted twice). Per rule: how many
numbers it removes, and where. The design card asks for at least 90 % kept.
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NUMBER = re.compile(r"\d+(?:[.,]\d+)*(?:[eE][+-]?\d+)?")


def rules(path: Path) -> list[tuple[str, str]]:
    """The (regex, replace) pairs of a sanitize file, read as nbval reads them (``get_sanitize_patterns``)."""
    return re.findall(r"^regex: (.*)$\n^replace: (.*)$", path.read_text(), flags=re.MULTILINE)


def texts(book: Path) -> list[str]:
    """The text outputs of a stored notebook, one string per checked cell and output kind (streams joined, as nbval does)."""
    cells = json.loads(book.read_text())["cells"]
    found = []
    for cell in cells:
        if cell["cell_type"] != "code" or "nbval-ignore-output" in cell["metadata"].get("tags", []):
            continue
        streams = {}
        for out in cell.get("outputs", []):
            if out["output_type"] == "stream":
                streams[out["name"]] = streams.get(out["name"], "") + "".join(out["text"])
            elif "text/plain" in out.get("data", {}):
                found.append("".join(out["data"]["text/plain"]))
        found.extend(streams.values())
    return found


def main(argv: list[str]) -> int:
    cfg = Path(argv[0]) if argv and argv[0].endswith(".cfg") else ROOT / "notebooks" / "nbval-sanitize.cfg"
    names = [a for a in argv if not a.endswith(".cfg")]
    books = [Path(n) for n in names] or sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")) + [ROOT / "notebooks" / "glossary.ipynb"]
    pairs = rules(cfg)
    assert not any(NUMBER.search(replace.replace("\\1", "").replace("\\2", "")) for _, replace in pairs), \
        "a replacement holds digits: the count after would be wrong"
    before = after = 0
    removed = {regex: {} for regex, _ in pairs}  # regex -> notebook -> numbers removed
    for book in books:
        for text in texts(book):
            before += len(NUMBER.findall(text))
            for regex, replace in pairs:
                new = re.sub(regex, replace, text)
                gone = len(NUMBER.findall(text)) - len(NUMBER.findall(new))
                if gone:
                    removed[regex][book.stem] = removed[regex].get(book.stem, 0) + gone
                text = new
            after += len(NUMBER.findall(text))
    print(f"{len(books)} notebooks, {len(pairs)} rules ({cfg.relative_to(ROOT) if cfg.is_relative_to(ROOT) else cfg})")
    for regex, where in removed.items():
        print(f"  {regex[:60]:60s} removes {sum(where.values()):4d}  {', '.join(f'{k}: {v}' for k, v in where.items())}")
    print(f"numbers in the stored text outputs: {before}; after the rules: {after}; kept {100 * after / max(before, 1):.1f} %")
    return 0 if after >= 0.9 * before else 1


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
