"""The API reference (docs/build_api.py: pdoc, numpy docstrings) builds without a warning, every module in it."""

import runpy
import warnings
from pathlib import Path

BUILD = Path(__file__).parents[1] / "docs" / "build_api.py"


def test_the_api_reference_builds_without_warnings_and_covers_every_module(tmp_path):
    script = runpy.run_path(str(BUILD))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        index = script["build"](tmp_path)
    assert [str(w.message) for w in caught] == []
    assert index.exists()
    names = script["modules"]()
    assert {"deformable.scenes", "deformable.physics.loads", "fdmodel.model", "femodel.model",
            "validation.commands.run"} <= set(names)
    for name in names:
        page = tmp_path.joinpath(*name.split(".")).with_suffix(".html")
        assert page.stat().st_size > 2_000, name
