"""Force models from scene-file tables as obstacles are (deformable.scenes.config.force_model_field): a
``[force_model]`` table, its ``kind`` and the model's own fields, beside the string form ``force_model = "..."``."""

import pytest

import deformable as dm
from deformable import scenes
from deformable.errors import InputError

KOITER = """scene = "hanging"
nodes = [6, 6]

[force_model]
kind = "koiter"
E = 2e5
nu = 0.3
h = 1e-3
"""


def test_a_table_of_a_model_without_fields_is_the_string_form():
    table = scenes.read_toml_text('scene = "hanging"\n[force_model]\nkind = "tpbf87"\n')
    string = scenes.read_toml_text('scene = "hanging"\nforce_model = "tpbf87"\n')
    assert table == string and table.force_model == "tpbf87"
    assert 'force_model = "tpbf87"' in scenes.to_toml(table)  # written back in the string form


def test_a_table_with_the_models_fields_builds_it_and_round_trips():
    cfg = scenes.read_toml_text(KOITER)
    assert cfg.force_model == dm.Koiter(E=2e5, nu=0.3, h=1e-3)
    assert scenes.build(cfg).force_model == dm.Koiter(E=2e5, nu=0.3, h=1e-3)
    text = scenes.to_toml(cfg)
    assert "[force_model]" in text and 'kind = "koiter"' in text
    assert scenes.read_toml_text(text) == cfg


@pytest.mark.parametrize("table, field, message", [
    ('kind = "tpbf88"', "force_model.kind", "scene field force_model.kind must be one of tpbf87, frozen, variational"),
    ("E = 1.0", "force_model.kind", "scene field force_model.kind must be one of .*got None"),
    ('kind = "koiter"\nthickness = 1.0', "force_model.thickness",
     "unknown key 'thickness' in scene field force_model of kind 'koiter'; known keys: kind, E, nu, h"),
    ('kind = "koiter"\nE = -1.0', "Koiter.E", "Koiter E must be a positive number"),
])
def test_a_bad_table_is_one_line_naming_the_field_and_the_known_names(table, field, message):
    with pytest.raises(InputError, match=message) as caught:
        scenes.read_toml_text(f'scene = "hanging"\n[force_model]\n{table}\n', source="s.toml")
    assert caught.value.field == field and "\n" not in str(caught.value)


def test_the_string_form_still_names_the_known_models():
    with pytest.raises(InputError, match="scene field force_model must be one of tpbf87") as caught:
        scenes.config("hanging", force_model="tpbf88")
    assert caught.value.field == "force_model"
