"""Sphinx configuration of the documentation site: ``python docs/build.py`` (``pip install ".[docs]"``).

The landing page is the README (docs/index.md includes it); the user guide and the pages beside it are MyST
markdown in docs/, with docs/design.md; the command line reference is a page per subcommand, rendered by
sphinx-argparse from the command's own parser; the API reference is a page per job (model, backends, contact,
dynamics, output, validation), autodoc over every module of the four packages (numpy docstrings through
napoleon); the examples gallery is sphinx-gallery running every script of examples/ and showing the PNGs it
writes; and the changelog is CHANGELOG.md. The generated pages (docs/api/, docs/cli/) are written here, from
docs/build.py, before Sphinx reads the sources.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))  # the source tree's packages, as the examples import them

from sphinx.ext import autosummary

import deformable

# docs/build.py as a module: the generated pages' contents, and the parser sphinx-argparse imports by name
_spec = importlib.util.spec_from_file_location("deformable_docs", HERE / "build.py")
SITE = sys.modules["deformable_docs"] = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(SITE)

project = "deformable-sheets"  # the distribution, as pip installs it; the import name is deformable
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
    "sphinxarg.ext",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "examples", "scenes", "Thumbs.db", ".DS_Store"]
html_theme = "furo"
html_title = f"deformable-sheets {release}"

myst_heading_anchors = 3  # links to sections of a page (guide.md#install)
myst_enable_extensions = ["dollarmath"]
smartquotes_action = "qe"  # quotes and ellipses; "--resume" in an option's help stays two hyphens
myst_ref_domains = ["std", "py"]  # a link to a name is looked up there (sphinx-argparse's domain resolves none)

# the API reference: a page per job, each module a section of it (docs/build.py, GROUPS); the tables of modules
# are autosummary's, with no page generated
API = HERE / "api"
shutil.rmtree(API, ignore_errors=True)
API.mkdir()
for _page, _names in SITE.api_groups().items():
    (API / f"{_page}.rst").write_text(SITE.api_page(_page, _names), encoding="utf-8")
autosummary_generate = False
# a module's summary is its docstring's first sentence, which "eq. (13)" and "Fig. 1" do not end (autosummary
# knows only "e.g.", "i.e.", "et al." and "vs.")
autosummary.WELL_KNOWN_ABBREVIATIONS = (*autosummary.WELL_KNOWN_ABBREVIATIONS, "eq.", "Eq.", "Fig.", "Figs.")

# the command line reference: a page per subcommand, and where the guide tells of it in words
CLI_GUIDE = {
    "scenes": ("the scenes", "../scenes.md"),
    "run": ("Running a scene", "../guide.md#running-a-scene"),
    "params": ("Viewing, parameters and checks", "../guide.md#viewing-parameters-and-checks"),
    "view": ("Viewing, parameters and checks", "../guide.md#viewing-parameters-and-checks"),
    "check": ("Viewing, parameters and checks", "../guide.md#viewing-parameters-and-checks"),
    "validate": ("Validation", "../validation.md"),
    "bench": ("Benchmarks", "../benchmarks.md"),
    "sweep": ("Sweeps, on a laptop or a cluster", "../guide.md#sweeps-on-a-laptop-or-a-cluster"),
    "fabrics": ("Force models, materials and fabrics", "../models.md#force-models-materials-and-fabrics"),
}
CLI = HERE / "cli"
shutil.rmtree(CLI, ignore_errors=True)
CLI.mkdir()
for _name in SITE.commands():
    (CLI / f"{_name}.md").write_text(SITE.cli_page(_name, guide=CLI_GUIDE.get(_name)), encoding="utf-8")

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


# the README on the landing page and the pages of docs/ link to the repository's files as GitHub shows them; on the
# site those links lead to its own pages (docs/build.py, site_links), and the generated tables fill their places


def _readme_links(app, relative_path, parent_docname, content):
    if Path(relative_path).name == "README.md":
        content[0] = SITE.site_links(content[0], ROOT, (HERE / parent_docname).parent)


def _page_links(app, docname, source):
    path = Path(app.env.doc2path(docname))
    if path.suffix == ".md":
        source[0] = SITE.fill_tables(SITE.site_links(source[0], path.parent, path.parent))


def setup(app):
    app.connect("autodoc-process-docstring", _escape_docstring)
    app.connect("include-read", _readme_links)
    app.connect("source-read", _page_links)


# the type words of a numpy docstring's fields ("array (ndof,)") are linked where a name matches; a word that
# names attributes of several classes (ndof) is then ambiguous; the site's own pickle cache cannot hold the
# gallery's scraper object
suppress_warnings = ["ref.python", "config.cache"]
