"""Sphinx configuration of the gridfield documentation (offline: no intersphinx)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))  # document this checkout's gridfield, not another installed copy
sys.path.insert(0, str(HERE))
os.environ.setdefault("MPLBACKEND", "Agg")

from _api import write_api_pages, write_cli_page  # noqa: E402

import gridfield  # noqa: E402

project = "gridfield"
author = "gridfield developers"
copyright = "gridfield developers, MIT licence"
version = release = gridfield.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

exclude_patterns = ["_build", "figures/README.md", "api/README.md", "**/GALLERY_HEADER.rst"]
templates_path: list[str] = []
html_theme = "furo"
html_static_path: list[str] = []
html_title = f"gridfield {release}"

# API reference: one page per public module, written from each module's __all__ on every build.
write_api_pages(HERE / "api")
write_cli_page(HERE / "cli.rst")  # the command-line reference, from the parsers
autosummary_generate = False
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,
    "min_reported_time": 1,
    "show_memory": False,
    "capture_repr": (),  # the last expression (an Artists record) is not printed
    "plot_gallery": "True",
    # an example that leaves a matplotlib Animation in its globals is embedded as a JavaScript
    # player (no ffmpeg needed); its gallery thumbnail is the example's first still figure
    "matplotlib_animations": (True, "jshtml"),
}
