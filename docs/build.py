"""Build the documentation site: ``python docs/build.py [OUT]`` (default docs/_build/html; ``pip install ".[docs]"``).

Sphinx with ``-W --keep-going``: every warning is reported and any warning fails the build (exit code 1), as CI
runs it. The examples gallery runs every script of examples/ (30 s on two cores); the build then fails too
when a module has no section in the API reference (:func:`api_gaps`), a subcommand of ``deformable`` no page in
the command line reference (:func:`cli_gaps`), or an example no gallery page or no picture it drew on its page
(:func:`gallery_gaps`).

What is generated, not written, comes from here (docs/conf.py writes the pages before Sphinx reads the sources):
the API reference's pages by job (:data:`GROUPS`, :func:`api_page`), a page for each subcommand (:func:`cli_page`,
rendered by sphinx-argparse from :func:`cli_parser`), the tables of both on their index pages
(:func:`fill_tables`), and the links of the README and of the pages to the repository's files, made links of the
site (:func:`site_links`).
"""

from __future__ import annotations

import os
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"


PACKAGES = ("deformable", "fdmodel", "femodel", "validation")

#: The API reference, a page per job: page -> (title, what its modules do, the packages and modules it holds).
#: A module belongs to the page holding the longest of its prefixes; each package's root is held, so every
#: module of the four packages has its page (a new one lands beside its package until it is placed).
GROUPS = {
    "model": ("Model", ("What a sheet is and what moves it: the tensors of eq. (4)-(8) and the sheet, the "
              "material, the force models of eq. (13)-(15) and any energy density one adds, forces and loads, a "
              "scene and its constraints, the catalogue of the paper's scenes and scene files; the exceptions and "
              "the checks of input every constructor runs."),
              ("deformable", "deformable.errors", "deformable.checks", "deformable.registry", "deformable.tomlio",
               "deformable.geometry", "deformable.physics", "deformable.scene", "deformable.scenes")),
    "backends": ("Backends", ("The discretisations and what they share: the contract every backend satisfies and "
                 "their registry, fixed-pattern sparse assembly and the solvers, the paper's finite differences "
                 "(fdmodel) and the finite elements (femodel)."),
                 ("deformable.backends", "deformable.algebra", "fdmodel", "femodel")),
    "contact": ("Contact", ("Obstacles (analytic and meshes), the barrier and the exponential force, self-contact "
                "and its contact mesh, friction, and the clearance of a state."),
                ("deformable.contact",)),
    "dynamics": ("Dynamics", ("The time stepping of eq. (22)-(27) and the implicit schemes under one controller, "
                 "its trackers, Newton's method and its line searches, equilibrium and its paths, and a run as one "
                 "object (Simulation)."),
                 ("deformable.dynamics", "deformable.solve", "deformable.session")),
    "output": ("Output", ("What a run writes and says: the XDMF series, checkpoints, rendered frames, the run "
               "folder, the memory and disk a run will need, and progress."),
               ("deformable.io", "deformable.progress", "deformable.limits")),
    "validation": ("Validation", ("The ``deformable`` command line, the study framework, the studies and the "
                   "benches."),
                   ("validation",)),
}


def modules(packages=PACKAGES) -> list[str]:
    """The packages and all their modules, by import name."""
    import importlib
    import pkgutil

    names = []
    for package in packages:
        names.append(package)
        names += [m.name for m in pkgutil.walk_packages(importlib.import_module(package).__path__, package + ".")]
    return names


def group_of(name: str, groups=GROUPS) -> str:
    """The API page of module ``name``: the group holding the longest of its prefixes."""
    held = [(len(prefix), page) for page, (_, _, prefixes) in groups.items() for prefix in prefixes
            if name == prefix or name.startswith(prefix + ".")]
    if not held:
        raise ValueError(f"{name}: no page of the API reference holds it (docs/build.py, GROUPS)")
    return max(held)[1]


def api_groups(names=None, groups=GROUPS) -> dict[str, list[str]]:
    """Each API page's modules, in the order of :func:`modules` (a package before its modules)."""
    pages = {page: [] for page in groups}
    for name in modules() if names is None else names:
        pages[group_of(name, groups)].append(name)
    return pages


def api_page(page: str, names, groups=GROUPS) -> str:
    """The reStructuredText of one API page: its title, what its modules do, a table of them, and each module
    from its docstrings (autodoc)."""
    title, about, _ = groups[page]
    lines = [title, "=" * len(title), "", about, "", ".. autosummary::", ""]
    lines += [f"   {name}" for name in names]
    for name in names:
        lines += ["", "", name, "-" * len(name), "", f".. automodule:: {name}", "   :members:",
                  "   :ignore-module-all:"]
    return "\n".join(lines) + "\n"


def api_gaps(html: Path, names=None) -> list[str]:
    """The modules with no section in the API reference built under ``html`` (``api/PAGE.html`` holding the
    module's target, ``id="module-NAME"``)."""
    names = modules() if names is None else list(names)
    if not names:
        return ["no module to document"]
    gaps, pages = [], {}
    for name in names:
        page = html / "api" / f"{group_of(name)}.html"
        if page not in pages:
            pages[page] = page.read_text(encoding="utf-8") if page.is_file() else ""
        if f'id="module-{name}"' not in pages[page]:
            gaps.append(f"{name}: no section in the API reference ({page.relative_to(html)})")
    return gaps


def commands() -> dict[str, str]:
    """The subcommands of ``deformable`` and their one-line help (validation.commands.COMMANDS)."""
    from validation.commands import COMMANDS

    return {name: help_ for name, (_, help_) in COMMANDS.items()}


def cli_parser():
    """The ``deformable`` parser with each option's help as ``--help`` prints it (the command line's formatter
    appends a default that the text does not state), for sphinx-argparse."""
    import argparse

    from validation.commands import HelpFormatter, build_parser

    parser = build_parser()
    subparsers = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    for p in [parser, *(sp for a in subparsers for sp in a.choices.values())]:
        formatter = HelpFormatter(p.prog)
        for action in p._actions:
            if action.help not in (None, argparse.SUPPRESS):
                action.help = formatter._get_help_string(action)
    return parser


def cli_page(name: str, module: str = "deformable_docs", guide: tuple[str, str] | None = None) -> str:
    """The MyST page of subcommand ``name``: sphinx-argparse over :func:`cli_parser` (importable as ``module``),
    after a link to the page that tells of the command in words, ``guide`` = (its text, its target relative to
    the page), if given."""
    lines = [f"# deformable {name}", ""]
    if guide:
        lines += [f"What it does and what it writes, in words: [{guide[0]}]({guide[1]}).", ""]
    lines += ["```{eval-rst}", ".. highlight:: none", "", ".. argparse::", f"   :module: {module}",
              "   :func: cli_parser", "   :prog: deformable", f"   :path: {name}", "   :nodefault:", "```"]
    return "\n".join(lines) + "\n"


def cli_gaps(html: Path, names=None) -> list[str]:
    """The subcommands with no page in the command line reference built under ``html`` (``cli/NAME.html`` with
    the command's usage)."""
    names = list(commands()) if names is None else list(names)
    if not names:
        return ["no subcommand to document"]
    pages = [(f"deformable {name}", html / "cli" / f"{name}.html", f"deformable {name} [-h]") for name in names]
    return page_gaps(pages, "no page in the command line reference", "its page shows no usage")


def page_gaps(pages, missing: str, lacking: str) -> list[str]:
    """The gaps among built pages, ``pages`` a list of (what the page is for, its path, a text it must hold): the
    page is ``missing``, or ``lacking`` that text."""
    gaps = []
    for what, page, mark in pages:
        if not page.is_file():
            gaps.append(f"{what}: {missing} ({page})")
        elif mark not in page.read_text(encoding="utf-8"):
            gaps.append(f"{what}: {lacking}")
    return gaps


# Markdown written for the repository links to its files by their paths; on the site, a link to a file that is no
# page of the site becomes a link of the site: an example script (examples/NAME.py) leads to its gallery page,
# examples/README.md to the gallery, CHANGELOG.md to the changelog page, README.md to the landing page; any
# other file (CITATION.cff, a report) is named as a literal
_LINK = re.compile(r"(?<!!)\[([^\]]*)\]\(([^)\s#:]+)(#[^)\s]*)?\)")
_SITE_FILES = {"examples/README.md": "auto_examples/index", "CHANGELOG.md": "changelog", "README.md": "index.md"}


def site_links(text: str, source: Path, page: Path, docs: Path = HERE) -> str:
    """``text``, markdown whose relative links start from the folder ``source``, with its links to repository
    files outside ``docs`` made links of the site, relative to the folder ``page`` of the page that shows it (the
    README: from the repository's root, shown on docs/index.md; a page of docs/: from its own folder)."""
    root = docs.parent

    def link(match):
        label, path, anchor = match.group(1), match.group(2), match.group(3) or ""
        target = (source / path).resolve()
        if target == docs or docs in target.parents:
            return match.group(0)  # a page or a picture of the site
        file = target.relative_to(root).as_posix() if root in target.parents else path
        example = re.fullmatch(r"examples/(\w+)\.py", file)
        site = f"auto_examples/{example.group(1)}" if example else _SITE_FILES.get(file)
        if site is None:
            return f"`{file}`" if label.strip("`") == file else f"{label} (`{file}`)"
        return f"[{label}]({Path(os.path.relpath(docs / site, page)).as_posix()}{anchor})"

    return _LINK.sub(link, text)


#: where a page of docs/ asks for a generated table: the subcommands (cli.md) and the API's pages (api.md)
CLI_TABLE = "<!-- cli-commands: docs/conf.py writes here a table of the subcommands, from validation.commands -->"
API_TABLE = "<!-- api-groups: docs/conf.py writes here a table of the pages and the modules each holds -->"


def fill_tables(text: str) -> str:
    """``text`` with the generated tables where it asks for them: each subcommand with its page and its one-line
    help, and each API page with what its modules do and how many it holds."""
    if CLI_TABLE in text:
        rows = [f"| [`deformable {name}`](cli/{name}.md) | {help_} |" for name, help_ in commands().items()]
        text = text.replace(CLI_TABLE, "\n".join(["| command | what it does |", "|---|---|", *rows]))
    if API_TABLE in text:
        rows = []
        for page, names in api_groups().items():
            title, about, prefixes = GROUPS[page]
            held = ", ".join(f"`{p}`" for p in prefixes)
            rows.append(f"| [{title}](api/{page}.rst) | {about.replace('``', '`')} | {len(names)}, in {held} |")
        text = text.replace(API_TABLE, "\n".join(["| page | what its modules do | modules |", "|---|---|---|", *rows]))
    return text


def gallery_gaps(html: Path, examples: Path = EXAMPLES) -> list[str]:
    """The examples the built gallery under ``html`` misses: no page, or a page with no image of the script's own
    output (sphinx-gallery's ``sphx_glr_NAME_NNN.png``). Empty when every example is there with its picture."""
    scripts = sorted(examples.glob("*.py"))
    if not scripts:
        return [f"no example scripts in {examples}"]
    pages = [(s.name, html / "auto_examples" / f"{s.stem}.html", f"sphx_glr_{s.stem}_001.png") for s in scripts]
    return page_gaps(pages, "no gallery page", "its gallery page shows no picture it drew")


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    out = Path(argv[0]) if argv else HERE / "_build" / "html"
    try:
        from sphinx.cmd.build import build_main
    except ImportError:
        print('docs/build.py needs sphinx: pip install ".[docs]"', file=sys.stderr)
        return 2
    code = build_main(["-E", "-W", "--keep-going", "-q", "-b", "html", "-d", str(HERE / "_build" / "doctrees"),
                       str(HERE), str(out)])
    if code:
        return code
    gaps = api_gaps(out) + cli_gaps(out) + gallery_gaps(out)
    for gap in gaps:
        print(f"docs/build.py: {gap}", file=sys.stderr)
    if not gaps:
        print(f"docs/build.py: the site is in {out}, no warning; {len(modules())} modules in the API reference on "
              f"{len(GROUPS)} pages by job, {len(commands())} subcommands each with its page, "
              f"{len(list(EXAMPLES.glob('*.py')))} examples in the gallery, each with its picture")
    return 1 if gaps else 0


if __name__ == "__main__":
    sys.exit(main())
