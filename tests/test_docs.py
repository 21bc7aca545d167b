"""The documentation site's own checks (docs/build.py): a module without its section in the API reference, a
subcommand without its page, an example without its gallery page or picture, is a gap that fails the build; the
API is grouped by job, every module in one group; the README's and the pages' links to repository files lead to
pages of the site. (CI builds the site itself: .ci/run.)"""

import runpy
from pathlib import Path

DOCS = Path(__file__).parents[1] / "docs"
BUILD = runpy.run_path(str(DOCS / "build.py"))


def test_the_site_documents_every_module_of_the_four_packages():
    names = BUILD["modules"]()
    assert {"deformable", "deformable.scenes.fields", "fdmodel.model", "femodel.model", "validation.commands.run"} \
        <= set(names)


def test_every_module_has_one_group_by_job_the_longest_prefix_deciding():
    group_of, groups = BUILD["group_of"], BUILD["api_groups"]()
    assert list(groups) == ["model", "backends", "contact", "dynamics", "output", "validation"]
    assert sorted(n for names in groups.values() for n in names) == sorted(BUILD["modules"]())
    assert all(groups.values())  # no empty page
    assert group_of("deformable") == group_of("deformable.scenes.fields") == group_of("deformable.scene") == "model"
    assert group_of("deformable.contact.barrier") == "contact" and group_of("deformable.io.render") == "output"
    assert group_of("fdmodel.model") == group_of("femodel") == group_of("deformable.algebra.solvers") == "backends"
    assert group_of("deformable.session.simulation") == "dynamics" and group_of("validation.commands") == "validation"
    assert group_of("deformable.newmodule") == "model"  # beside its package until it is placed
    assert group_of("deformable.contacts") == "model"  # a prefix is a whole package, not the start of a name
    page = BUILD["api_page"]("contact", ["deformable.contact", "deformable.contact.barrier"])
    assert page.startswith("Contact\n=======\n") and ".. automodule:: deformable.contact.barrier" in page


def test_an_api_section_missing_is_a_gap(tmp_path):
    (tmp_path / "api").mkdir()
    (tmp_path / "api" / "model.html").write_text('<section id="module-deformable"></section>')
    assert BUILD["api_gaps"](tmp_path, ["deformable"]) == []
    assert BUILD["api_gaps"](tmp_path, ["deformable", "deformable.errors"]) \
        == ["deformable.errors: no section in the API reference (api/model.html)"]
    assert BUILD["api_gaps"](tmp_path, ["fdmodel"]) == ["fdmodel: no section in the API reference (api/backends.html)"]
    assert BUILD["api_gaps"](tmp_path, []) != []


def test_a_subcommand_without_its_page_is_a_gap(tmp_path):
    assert {"run", "view", "validate", "bench", "sweep"} <= set(BUILD["commands"]())
    (tmp_path / "cli").mkdir()
    (tmp_path / "cli" / "run.html").write_text("<pre>usage: deformable run [-h] [--backend NAME]</pre>")
    (tmp_path / "cli" / "view.html").write_text("<p>no usage</p>")
    assert BUILD["cli_gaps"](tmp_path, ["run"]) == []
    gaps = BUILD["cli_gaps"](tmp_path, ["run", "view", "sweep"])
    assert gaps[0] == "deformable view: its page shows no usage" and gaps[1].startswith("deformable sweep: no page")
    assert BUILD["cli_gaps"](tmp_path, []) != []


def test_a_subcommand_page_is_its_parser_with_the_help_as_help_prints_it():
    page = BUILD["cli_page"]("run", guide=("Running a scene", "../guide.md#running-a-scene"))
    assert page.startswith("# deformable run\n") and "[Running a scene](../guide.md#running-a-scene)" in page
    assert ":path: run" in page and ":func: cli_parser" in page
    run = next(a for a in BUILD["cli_parser"]()._actions if a.dest == "command").choices["run"]
    field = next(a for a in run._actions if a.dest == "field")
    assert field.help.endswith("(default: %(default)s)")  # what the command line's own formatter appends


def test_the_links_to_repository_files_lead_to_pages_of_the_site():
    site_links, root = BUILD["site_links"], DOCS.parent
    readme = ("[guide](docs/guide.md#install) [fd_vs_fe.py](examples/fd_vs_fe.py) [examples/](examples/README.md) "
              "[Changelog](CHANGELOG.md) [CITATION.cff](CITATION.cff) ![curtain](docs/scenes/curtain.gif)")
    assert site_links(readme, root, DOCS) == (
        "[guide](docs/guide.md#install) [fd_vs_fe.py](auto_examples/fd_vs_fe) [examples/](auto_examples/index) "
        "[Changelog](changelog) `CITATION.cff` ![curtain](docs/scenes/curtain.gif)")
    page = "[start](../README.md#quick-start) [models](models.md#x) [a report](../reports/paper/summary.md)"
    assert site_links(page, DOCS, DOCS) == \
        "[start](index.md#quick-start) [models](models.md#x) a report (`reports/paper/summary.md`)"
    assert site_links("[guide](../guide.md#running-a-scene) [x](../../CHANGELOG.md)", DOCS / "cli", DOCS / "cli") \
        == "[guide](../guide.md#running-a-scene) [x](../changelog)"


def test_the_index_pages_get_their_generated_tables():
    cli = BUILD["fill_tables"](BUILD["CLI_TABLE"])
    assert "| [`deformable run`](cli/run.md) | run a scene" in cli
    api = BUILD["fill_tables"](BUILD["API_TABLE"])
    assert api.count("\n| [") == 6 and "| [Contact](api/contact.rst) |" in api
    for page, mark in (("cli.md", "CLI_TABLE"), ("api.md", "API_TABLE")):
        assert BUILD[mark] in (DOCS / page).read_text()


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
