"""The documentation site's own checks (docs/build.py): a module without an API page, an example without its
gallery page or picture, is a gap that fails the build. (CI builds the site itself: .ci/run.)"""

import runpy
from pathlib import Path

BUILD = runpy.run_path(str(Path(__file__).parents[1] / "docs" / "build.py"))


def test_the_site_documents_every_module_of_the_four_packages():
    names = BUILD["modules"]()
    assert {"deformable", "deformable.scenes.fields", "fdmodel.model", "femodel.model", "validation.commands.run"} \
        <= set(names)


def test_an_api_page_missing_is_a_gap(tmp_path):
    (tmp_path / "api").mkdir()
    (tmp_path / "api" / "deformable.html").write_text("<html/>")
    assert BUILD["api_gaps"](tmp_path, ["deformable"]) == []
    assert BUILD["api_gaps"](tmp_path, ["deformable", "fdmodel"]) == ["fdmodel: no page in the API reference"]
    assert BUILD["api_gaps"](tmp_path, []) != []


def test_an_example_without_its_page_or_its_picture_is_a_gap(tmp_path):
    examples, html = tmp_path / "examples", tmp_path / "html"
    (html / "auto_examples").mkdir(parents=True)
    examples.mkdir()
    assert BUILD["gallery_gaps"](html, examples) != []  # no example: not a complete gallery
    for name in ("drawn", "blank", "absent"):
        (examples / f"{name}.py").write_text('"""An example\n==========\n"""\n')
    (html / "auto_examples" / "drawn.html").write_text('<img src="../_images/sphx_glr_drawn_001.png">')
    (html / "auto_examples" / "blank.html").write_text("<p>code only</p>")
    gaps = BUILD["gallery_gaps"](html, examples)
    assert len(gaps) == 2 and gaps[0].startswith("absent.py: no gallery page") and gaps[1].startswith("blank.py")
