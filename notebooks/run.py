"""Run the notebooks through papermill with a preset: ``python notebooks/run.py --preset paper``.

Executed copies go to ``build/<preset>/`` (ignored by git). Figures go to ``figures/`` for the paper preset
(committed) and to ``build/figures-ci/`` for the ci preset, so a quick run never overwrites them.
The ci preset is each notebook's own parameters cell; ``notebooks/params/<preset>.yaml`` overrides
it per notebook (a section named after the notebook).
"""
from __future__ import annotations

import argparse
import sys
import time

import papermill
import yaml

from ifslib.paths import figures_dir, repo_root


def presets(name: str) -> dict:
    """Per-notebook parameters of a preset (``ci``: none, the notebooks' defaults)."""
    path = repo_root() / "notebooks" / "params" / f"{name}.yaml"
    if name == "ci" and not path.exists():
        return {}
    if not path.exists():
        sys.exit(f"no preset {name!r}: {path} does not exist")
    return yaml.safe_load(path.read_text()) or {}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="paper", help="paper (default) or ci")
    parser.add_argument("--only", nargs="*", default=[], help="notebook name prefixes, e.g. 02 04")
    args = parser.parse_args(argv)
    root = repo_root()
    params = presets(args.preset)
    out = root / "build" / args.preset
    save_to = figures_dir() if args.preset == "paper" else root / "build" / f"figures-{args.preset}"
    books = sorted((root / "notebooks").glob("[0-9][0-9]_*.ipynb"))
    books = [b for b in books if not args.only or any(b.stem.startswith(p) for p in args.only)]
    out.mkdir(parents=True, exist_ok=True)
    for book in books:
        started = time.perf_counter()
        print(f"== {book.name} ({args.preset} preset)", flush=True)
        values = dict(params.get(book.stem, {}))
        if "save_to" in papermill.inspect_notebook(str(book)):
            values["save_to"] = str(save_to)
        papermill.execute_notebook(str(book), str(out / book.name), cwd=str(book.parent), kernel_name="python3",
                                   parameters=values, progress_bar=True)
        print(f"   {time.perf_counter() - started:.1f} s -> {out.relative_to(root) / book.name}", flush=True)
    print(f"figures in {save_to}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
