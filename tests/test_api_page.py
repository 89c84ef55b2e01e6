"""The API reference (docs/api/index.md) lists every public name, so a name exported later without a page
entry fails here, not only in ``make book`` (whose ``_complete_api`` would file it under "Other public names").

The page is read as text: each ``{eval-rst}`` block's ``.. currentmodule::`` and the names of its
``.. autosummary::`` directive. No Sphinx, and nothing imported but ``ifslib`` (lazy: no torch);
``ifslib.splatting``'s names are read from its ``__init__.py`` without importing it.
"""
import ast
import re
from pathlib import Path

import ifslib

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "api" / "index.md"
SPLATTING = ROOT / "ifslib" / "splatting" / "__init__.py"


def listed(page: str | None = None) -> dict[str, list[str]]:
    """Each current module of the page's ``{eval-rst}`` blocks -> the names its autosummary blocks list, in order."""
    page = PAGE.read_text(encoding="utf-8") if page is None else page
    found: dict[str, list[str]] = {}
    for block in re.findall(r"^```\{eval-rst\}\n(.*?)^```", page, flags=re.M | re.S):
        module = None
        lines = block.splitlines()
        for i, line in enumerate(lines):
            current = re.match(r"\.\. currentmodule::\s*(\S+)\s*$", line)
            if current:
                module = current.group(1)
            elif re.match(r"\.\. autosummary::\s*$", line):
                assert module, f"an autosummary block without a currentmodule: {block!r}"
                for entry in lines[i + 1:]:
                    if entry and not entry.startswith(" "):
                        break  # the next directive
                    name = entry.strip()
                    if name and not name.startswith(":"):  # options (:toctree:, :nosignatures:) and blank lines
                        found.setdefault(module, []).append(name)
    return found


def module_all(path: Path) -> list[str]:
    """A module's ``__all__``, read from its source (a list or tuple of string literals)."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in node.targets):
            return list(ast.literal_eval(node.value))
    raise AssertionError(f"no __all__ in {path}")


def test_parser_reads_the_page_structure():
    page = ("```{eval-rst}\n.. currentmodule:: ifslib\n\n.. autosummary::\n   :toctree: generated\n"
            "   :nosignatures:\n\n   fit\n   render\n```\n\n- fit_splat\n\n```{eval-rst}\n"
            ".. currentmodule:: ifslib.splatting\n\n.. autosummary::\n   :toctree: generated\n\n   fit_splat\n```\n")
    assert listed(page) == {"ifslib": ["fit", "render"], "ifslib.splatting": ["fit_splat"]}


def test_every_public_name_has_an_entry():
    names = listed().get("ifslib", [])
    missing = [name for name in ifslib.__all__ if name not in names]
    assert not missing, f"ifslib.__all__ names with no entry under `.. currentmodule:: ifslib` in {PAGE}: {missing}"


def test_every_entry_is_public_and_listed_once():
    names = listed().get("ifslib", [])
    assert not [name for name in names if name not in ifslib.__all__], "an entry that is not in ifslib.__all__"
    assert len(names) == len(set(names)), sorted({name for name in names if names.count(name) > 1})


def test_splatting_names_have_entries():
    public = module_all(SPLATTING)
    names = listed().get("ifslib.splatting", [])
    assert sorted(names) == sorted(public), (f"`.. currentmodule:: ifslib.splatting` in {PAGE} lists {sorted(names)}, "
                                             f"ifslib.splatting.__all__ is {sorted(public)}")

