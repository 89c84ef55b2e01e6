"""Sphinx configuration for the ifslib notebook book (``make book``).

The source tree is not this folder: ``docs/build.py`` assembles it in ``build/book/src`` from
``docs/index.md``, README.md, ``figures/`` and ``notebooks/[0-9][0-9]_*.ipynb`` and runs
``sphinx-build -c docs`` on it. The notebooks are rendered from their stored outputs (the ci
preset), never executed, and nothing is fetched from the network at build time.
"""

project = "ifslib"
author = "ifslib contributors"
copyright = "ifslib contributors"

extensions = ["myst_nb"]  # MyST-NB also loads myst_parser

root_doc = "index"
# README.md is copied beside index.md only to be included by it; it is not a page of its own.
exclude_patterns = ["README.md", "_build", "**.ipynb_checkpoints"]

# --- MyST / MyST-NB ---------------------------------------------------------------------------
nb_execution_mode = "off"  # stored outputs only: the notebooks are executed by `make figures`
nb_merge_streams = True  # one block per cell for consecutive stdout/stderr writes
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3  # README-style `[text](#section)` links resolve to headings

# --- HTML -------------------------------------------------------------------------------------
html_theme = "sphinx_book_theme"
html_title = "ifslib"
html_theme_options = {
    "show_toc_level": 2,
    "home_page_in_toc": True,
}

# No intersphinx and no other extension that reaches the network.
nitpicky = True
