"""The scene catalogue and the shared options: ``deformable scenes``, ``--show-config``, the registries' choices
in ``--help``, ``sweep`` taking ``run``'s options, ``--compress`` and ``--render`` without its extra."""

import csv
import re
import sys
from dataclasses import fields

import h5py
import pytest

from deformable import scenes
from deformable.backends.registry import Discretisation
from deformable.physics.force_models import ForceModel
from validation.commands import main


def _main(argv, capsys):
    code = main([*map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_the_catalogue_lists_every_registered_scene_once_with_its_summary(capsys):
    code, out, _ = _main(["scenes"], capsys)
    names = list(scenes.SCENES)
    assert code == 0 and names, "no scene registered"
    lines = out.splitlines()
    assert [line.split()[0] for line in lines] == names
    for line, name in zip(lines, names):
        assert scenes.SCENES[name].summary and line.endswith(scenes.SCENES[name].summary)


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_every_field_of_every_scene_has_a_meaning_and_a_unit(name):
    cfg = scenes.config(name)
    docs = scenes.field_docs(type(cfg))
    names = [f.name for f in fields(cfg)]
    assert names
    missing = [n for n in names if n not in docs or not docs[n].meaning or not docs[n].unit]
    assert not missing, f"{name}: fields without 'meaning (unit).' in their config class's docstring: {missing}"


def test_show_config_prints_every_field_marks_the_overrides_and_runs_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code, out, _ = _main(["run", "curtain", "fabric=\"\"", "eta=25", "--grid", "8x8", "--show-config"], capsys)
    assert code == 0
    rows = {line.split()[0]: line for line in out.splitlines()[2:]}
    cfg = scenes.config("curtain")
    assert set(rows) == {f.name for f in fields(cfg)}
    assert "25 *" in rows["eta"] and "N/m" in rows["eta"] and "Stretching weight" in rows["eta"]
    assert "(8, 8) *" in rows["nodes"]
    assert "*" not in rows["xi"].split("N m")[0]
    assert not any(tmp_path.iterdir()), "--show-config wrote something"


@pytest.mark.parametrize("command", ["run", "params", "sweep"])
def test_backend_and_force_model_help_list_the_registered_choices(command, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = re.sub(r"-\s+", "-", " ".join(capsys.readouterr().out.split()))  # argparse wraps after a hyphen
    for name in (*Discretisation.names(), *ForceModel.names()):
        assert name in text, f"deformable {command} --help does not name {name}"


def test_sweep_takes_runs_options(tmp_path, capsys):
    out = tmp_path / "out"
    code, _, err = _main(["sweep", "hanging", "eta=10,20", "--grid", "6x6", "--dt", "0.005", "--t-end", "0.02",
                          "--out", out], capsys)
    assert code == 0, err
    with open(out / "sweep.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [r["eta"] for r in table] == ["10.0", "20.0"]
    assert {r["steps"] for r in table} == {"4"} and {r["t (s)"] for r in table} == {"0.02"}
    assert "--grid 6x6" in (out / "sweep.md").read_text()


@pytest.mark.parametrize("twice", [["t_end=0.02", "--t-end", "0.02"], ["nodes=6x6", "--grid", "6x6"]])
def test_a_sweep_key_given_also_as_an_option_is_one_line_and_writes_nothing(twice, tmp_path, capsys):
    code, _, err = _main(["sweep", "hanging", "eta=10,20", *twice, "--out", tmp_path / "out"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "give it one way" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("flag, compression", [("--compress", "gzip"), ("--no-compress", None)])
def test_compress_reaches_the_series_datasets(flag, compression, tmp_path, capsys):
    code, _, err = _main(["run", "hanging", "--grid", "6x6", "--steps", "2", flag, "--out", tmp_path], capsys)
    assert code == 0, err
    found = []
    with h5py.File(tmp_path / "hanging.h5") as f:
        f.visititems(lambda _, o: found.append(o.compression) if isinstance(o, h5py.Dataset) else None)
    assert found and set(found) == {compression}


def test_render_without_its_extra_is_one_line_naming_it_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pyvista", None)  # import pyvista raises ImportError, as on the core install
    code, _, err = _main(["run", "hanging", "--grid", "6x6", "--steps", "2", "--render", "--out", tmp_path / "out"],
                         capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "deformable-sheets[render]" in err and "--render" in err
    assert not (tmp_path / "out").exists()
