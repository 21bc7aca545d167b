"""Sphinx configuration of the documentation site: ``python docs/build.py`` (``pip install ".[docs]"``).

The user guide is the README and docs/design.md (MyST markdown, included as they are), the API reference is
autodoc over the four packages (numpy docstrings through napoleon), the examples gallery is sphinx-gallery
running every script of examples/ and showing the PNGs it writes, and the changelog is CHANGELOG.md.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # the source tree's packages, as the examples import them

import deformable

project = "deformable"
author = "the deformable developers"
copyright = "2026, " + author
release = version = deformable.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "examples", "scenes", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]
html_theme = "furo"
html_title = f"deformable {release}"

myst_heading_anchors = 3  # the README's links to its own sections (#quick-start)
myst_enable_extensions = ["dollarmath"]

autosummary_generate = True
autosummary_ignore_module_all = True  # every submodule gets its page, not only those a package exports
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True  # an Attributes section as fields of its class, not a second description of each

# every example runs; its figures are the PNGs it writes into EXAMPLES_OUT (examples/README.md)
OUT = Path(tempfile.mkdtemp(prefix="deformable-gallery-"))
os.environ["EXAMPLES_OUT"] = str(OUT)
os.environ.setdefault("MPLBACKEND", "Agg")


class WrittenPNGs:
    """A sphinx-gallery image scraper: the PNGs an example wrote into EXAMPLES_OUT since the last block.

    (The examples save their pictures with matplotlib or pyvista and close them, so the gallery shows the
    files they write, as a user running them gets them.)
    """

    def __init__(self):
        self.seen = set()

    def __repr__(self):  # sphinx-gallery keys its cache on the scraper's repr
        return "WrittenPNGs"

    def __call__(self, block, block_vars, gallery_conf):
        from sphinx_gallery.scrapers import figure_rst

        new = sorted(p for p in OUT.rglob("*.png") if p not in self.seen)
        self.seen.update(new)
        paths = []
        for png, target in zip(new, block_vars["image_path_iterator"]):
            shutil.copyfile(png, target)
            paths.append(target)
        return figure_rst(paths, gallery_conf["src_dir"])


sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r".*\.py$",  # run them all
    "image_scrapers": (WrittenPNGs(),),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "reset_argv": lambda gallery_conf, script_vars: [],
}

# Two plain-text notations of the docstrings that reStructuredText reads otherwise: a shape's starred axes,
# ``(2, 2, *pts)``, and a norm or absolute value, ``|r_1 x r_2|``. Both are escaped before autodoc parses a
# docstring (outside literals, and not on the lines of a table or line block); the text is shown as written.
_CODE = re.compile(r"(``.*?``|`[^`]*`)")
_STAR = re.compile(r"\*(?=[A-Za-z_]\w*\s*[),\]])")  # "*pts)" or "*S," : an unpacked shape, never emphasis
_DBARS = re.compile(r"\|\|([^|`\n]+?)\|\|")  # ||F||: a norm too
_BARS = re.compile(r"(?<![\\|])\|(?=[^\s|])([^|`\n]*?[^\s|\\])\|(?!\|)")  # |x|, |u - v|: a norm


def plain_notation(text: str) -> str:
    """``text`` with the shapes' stars and the norms' bars escaped for reStructuredText, outside literals."""
    parts = _CODE.split(text)
    for k in range(0, len(parts), 2):
        text = _DBARS.sub(r"\\|\\|\1\\|\\|", _STAR.sub(r"\\*", parts[k]))
        parts[k] = _BARS.sub(r"\\|\1\\|", text)
    return "".join(parts)


def _escape_docstring(app, what, name, obj, options, lines):
    for k, line in enumerate(lines):
        bare = line.strip()
        if not (bare.startswith("+-") or (bare.startswith("|") and bare.endswith("|") and bare.count("|") > 2)):
            lines[k] = plain_notation(line)


# the README's links to files of the repository, made for the site: an example script (examples/NAME.py) leads
# to its gallery page, examples/README.md to the gallery, CHANGELOG.md to the changelog page; any other file
# that is no page of the site (CITATION.cff) is named as a literal
_EXAMPLE_LINK = re.compile(r"\]\(examples/([A-Za-z0-9_]+)\.py\)")
_FILE_LINK = re.compile(r"\[([^\]]+)\]\(([A-Za-z0-9_.-]+\.(?:cff|toml|txt))\)")


def readme_for_site(text: str) -> str:
    """The README's markdown with its links to repository files turned into links of the site."""
    text = _EXAMPLE_LINK.sub(r"](auto_examples/\1)", text)
    text = text.replace("](examples/README.md)", "](auto_examples/index)").replace("](CHANGELOG.md)", "](changelog)")
    return _FILE_LINK.sub(r"`\2`", text)


def _readme_links(app, relative_path, parent_docname, content):
    content[0] = readme_for_site(content[0])


def setup(app):
    app.connect("autodoc-process-docstring", _escape_docstring)
    app.connect("include-read", _readme_links)


# the type words of a numpy docstring's fields ("array (ndof,)") are linked where a name matches; a word that
# names attributes of several classes (ndof) is then ambiguous; the site's own pickle cache cannot hold the
# gallery's scraper object
suppress_warnings = ["ref.python", "config.cache"]
