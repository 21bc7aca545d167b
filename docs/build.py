"""Build the documentation site: ``python docs/build.py [OUT]`` (default docs/_build/html; ``pip install ".[docs]"``).

Sphinx with ``-W --keep-going``: every warning is reported and any warning fails the build (exit code 1), as CI
runs it. The examples gallery runs every script of examples/ (30 s on two cores); the build then fails too
when a module has no page in the API reference (:func:`api_gaps`), or an example no gallery page or no picture
it drew on its page (:func:`gallery_gaps`).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"


PACKAGES = ("deformable", "fdmodel", "femodel", "validation")


def modules(packages=PACKAGES) -> list[str]:
    """The packages and all their modules, by import name."""
    import importlib
    import pkgutil

    names = []
    for package in packages:
        names.append(package)
        names += [m.name for m in pkgutil.walk_packages(importlib.import_module(package).__path__, package + ".")]
    return names


def api_gaps(html: Path, names=None) -> list[str]:
    """The modules with no page in the API reference built under ``html`` (``api/NAME.html``)."""
    names = modules() if names is None else list(names)
    if not names:
        return ["no module to document"]
    return [f"{n}: no page in the API reference" for n in names if not (html / "api" / f"{n}.html").is_file()]


def gallery_gaps(html: Path, examples: Path = EXAMPLES) -> list[str]:
    """The examples the built gallery under ``html`` misses: no page, or a page with no image of the script's own
    output (sphinx-gallery's ``sphx_glr_NAME_NNN.png``). Empty when every example is there with its picture."""
    gaps = []
    scripts = sorted(examples.glob("*.py"))
    if not scripts:
        return [f"no example scripts in {examples}"]
    for script in scripts:
        page = html / "auto_examples" / f"{script.stem}.html"
        if not page.is_file():
            gaps.append(f"{script.name}: no gallery page ({page})")
        elif f"sphx_glr_{script.stem}_001.png" not in page.read_text(encoding="utf-8"):
            gaps.append(f"{script.name}: its gallery page shows no picture it drew")
    return gaps


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
    gaps = api_gaps(out) + gallery_gaps(out)
    for gap in gaps:
        print(f"docs/build.py: {gap}", file=sys.stderr)
    if not gaps:
        print(f"docs/build.py: the site is in {out}, no warning; {len(modules())} modules in the API reference, "
              f"{len(list(EXAMPLES.glob('*.py')))} examples in the gallery, each with its picture")
    return 1 if gaps else 0


if __name__ == "__main__":
    sys.exit(main())
