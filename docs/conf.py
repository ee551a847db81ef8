"""Sphinx configuration of tumble's documentation: ``make docs`` builds it into out/docs."""

from __future__ import annotations

import sys
from pathlib import Path

import tumble

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "tumble"
author = "tumble developers"
copyright = "2026, tumble developers"  # noqa: A001 (Sphinx's name)
release = tumble.__version__
version = release

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    # MathJax 3 copied into the site's own _static: the equations render offline.
    "sphinx-mathjax-offline",
    "tumble_docs",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
# The tables included by performance.md are not pages of their own.
exclude_patterns = [
    "_build",
    "performance-tables.md",
    "orbit-year-table.md",
    "sunlight-year-table.md",
    "crossings-table.md",
    "capture-table.md",
    "averaged-floor-table.md",
]

# Equations: $…$ and $$…$$ in Markdown; \\tag{1.1} keeps a paper's own equation number.
mathjax3_config = {"tex": {"tags": "none"}}

# Markdown: $…$ maths, ::: fences, anchors for the ## and ### headings (links within a page).
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# The API reference: one page per public name, from the numpydoc docstrings.
autosummary_generate = True
autodoc_typehints = "none"  # the numpydoc Parameters sections give the types with their units
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_title = f"tumble {release}"
html_theme_options = {
    "navigation_depth": 2,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path = ["_static"]
