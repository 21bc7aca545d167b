"""Build the API reference from the docstrings: ``python docs/build_api.py [OUT]`` (default docs/api).

Every module of the four packages (deformable, fdmodel, femodel, validation),
numpy-style docstrings, LaTeX math; pdoc (``pip install ".[docs]"``).
"""

from __future__ import annotations

import contextlib
import pkgutil
import sys
import tempfile
from pathlib import Path

PACKAGES = ("deformable", "fdmodel", "femodel", "validation")


def modules() -> list[str]:
    """The packages and all their modules, by import name."""
    import importlib

    names = []
    for package in PACKAGES:
        names.append(package)
        pkg = importlib.import_module(package)
        names += [m.name for m in pkgutil.walk_packages(pkg.__path__, prefix=package + ".")]
    return names


def specs() -> list[str]:
    """What to hand pdoc: the packages, and the modules a package's ``__all__`` leaves out of its walk."""
    from pdoc.extract import walk_specs

    out = list(PACKAGES)
    covered = set(walk_specs(out))
    for m in modules():
        if m not in covered:  # a hidden package brings its own walk: each module is handed over once
            out.append(m)
            covered |= set(walk_specs([m]))
    return out


def build(out) -> Path:
    """Write the HTML reference into ``out``; returns the path of its index page."""
    import pdoc
    import pdoc.render

    pdoc.render.configure(docformat="numpy", math=True)
    out = Path(out).resolve()
    # away from the source tree: pdoc asks whether "deformable" means the folder here or the imported package
    with contextlib.chdir(tempfile.gettempdir()):
        pdoc.pdoc(*specs(), output_directory=out)
    return out / "index.html"


if __name__ == "__main__":
    print(build(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parent / "api"))
