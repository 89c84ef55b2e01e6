"""Sphinx configuration for the ifslib book (``make book``): the notebooks, the measured results, the API.

The source tree is not this folder: ``docs/build.py`` assembles it in ``build/book/src`` from
``docs/index.md``, README.md, ``figures/``, ``notebooks/[0-9][0-9]_*.ipynb`` and the pages under
``docs/`` (kept at ``docs/...`` there, so links resolve alike on GitHub and in the book) and runs
``sphinx-build -c docs`` on it. The notebooks are rendered from their stored outputs (the
teaching run), never executed; the API reference is generated from the docstrings (autodoc,
autosummary, napoleon for the numpy style); nothing is fetched from the network at build time.
"""

from pathlib import Path

project = "ifslib"
author = "ifslib contributors"
copyright = "ifslib contributors"

extensions = [
    "myst_nb",  # MyST-NB also loads myst_parser
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",  # the docstrings' numpy style (Parameters, Returns, ...)
]

root_doc = "index"
# README.md is copied beside index.md only to be included by it; it is not a page of its own.
exclude_patterns = ["README.md", "_build", "**.ipynb_checkpoints"]
# A page added at docs/NAME.md or docs/results/NAME.md joins the index's toctree through a glob;
# until one exists that glob matches nothing, which is not an error.
suppress_warnings = ["toc.empty_glob"]

# --- API reference (docs/api/index.md) --------------------------------------------------------
# docs/_templates/autosummary: classes with their members, modules with theirs (an absolute path:
# autosummary looks for templates relative to the source tree, which is build/book/src)
templates_path = [str(Path(__file__).resolve().parent / "_templates")]
autosummary_generate = True  # one page per public name, written into build/book/src only
autosummary_ignore_module_all = False
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"  # the docstrings say the types (and tensor shapes) in words
autodoc_preserve_defaults = True  # `lr=0.003`, not a folded constant
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False  # "Returns" reads as one paragraph, as written
# The docstrings write `ifslib.fit`, `run`, `Target` in backticks: a link where the name is
# documented, code text where it is not (a helper, a local name).
default_role = "py:obj"
add_module_names = False

# --- MyST / MyST-NB ---------------------------------------------------------------------------
nb_execution_mode = "off"  # stored outputs only: the notebooks are executed by `make figures`
nb_merge_streams = True  # one block per cell for consecutive stdout/stderr writes
# No widget manager from a CDN (require.js, @jupyter-widgets/html-manager): the book is read offline, and a
# stored widget (a progress bar) shows its text form instead.
nb_ipywidgets_js = {}
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3  # README-style `[text](#section)` links resolve to headings

# --- HTML -------------------------------------------------------------------------------------
html_theme = "sphinx_book_theme"
html_title = "ifslib"
html_theme_options = {
    "show_toc_level": 2,
    "home_page_in_toc": True,
}
# The theme's script reads the light/dark mode from here; left empty it logs "Got invalid theme
# mode" as a console error on every page a new visitor opens.
html_context = {"default_mode": "auto"}

# The formulas are typeset by the MathJax that docs/build.py copies from build/npm (make book
# installs it from the npm registry) into the book's _static: no page loads it from a CDN.
html_static_path = [str(Path(__file__).resolve().parent.parent / "build" / "book" / "static"),
                    str(Path(__file__).resolve().parent / "_static")]
# the notebooks' code at a size whose 88 characters fit the column (see _static/ifslib.css)
html_css_files = ["ifslib.css"]
mathjax_path = "mathjax/tex-mml-chtml.js"

# No intersphinx and no other extension that reaches the network.
nitpicky = True
# What nitpicky may not resolve without intersphinx: the types the docstrings name in words
# ("(n, 2) tensor", "str or callable", torch.Tensor, numpy arrays, path), and backtick names that
# are not public (see default_role). A reference to a documented ifslib name is still checked.
# Docstrings inside the package also name internal paths (ifslib.core.fitting.run.run, the module
# ifslib.core.fitting.strategies, ifslib.automatic.plan.discover) that the reference documents under
# their public names only: the core's folders, the extensions' and the top-level helpers'.
_INTERNAL = r"ifslib\.(core|automatic|measures|compression|splatting|learned|studies|teaching|names)\..*"
# Names that docstrings spell as they once were (to correct in the code; listed so a new one fails).
_STALE = [r"ifslib\.distance\.distance_fields", r"ifslib\.leaves\.expand_batch", r"ifslib\.rules",
          r'ifslib\.initialize\("auto", target\)', r"ifslib\.strategies\.STRATEGIES"]
nitpick_ignore_regex = [
    ("py:class", r"(?!ifslib\.).*"),
    ("py:obj", r"(?!ifslib\.).*"),
    ("py:exc", r"(?!ifslib\.).*"),
    *[(role, _INTERNAL) for role in ("py:obj", "py:class")],
    *[("py:obj", name) for name in _STALE],
]
