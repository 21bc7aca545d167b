"""Every unknown name gets the closest known one, by difflib (issue 47, point 6): scene keys, scenes and every
registry family; one line, the known names still listed; a name close to none gets no suggestion."""

import pytest

from deformable import scenes
from deformable.backends import Discretisation
from deformable.checks import known_keys, suggest
from deformable.contact import Obstacle
from deformable.dynamics import Scheme
from deformable.errors import InputError
from deformable.physics import ForceModel
from deformable.scenes import SceneConfig
from deformable.solve import LineSearch


def _message(call) -> str:
    with pytest.raises(InputError) as err:
        call()
    message = str(err.value)
    assert "\n" not in message
    return message


@pytest.mark.parametrize("name, known, expected", [
    ("etaa", ["alpha", "eta", "xi"], " (did you mean 'eta'?)"),
    ("Eta", ["alpha", "eta", "xi"], " (did you mean 'eta'?)"),
    ("curtian", ["curtain", "curtain-silky", "paper"], " (did you mean 'curtain'?)"),
    ("tablecloth", ["curtain", "paper"], ""),
    ("fx", ["fd", "fe"], ""),  # one letter in two: not close enough
    (3, ["eta"], ""),
    ("eta", [], ""),
])
def test_suggest(name, known, expected):
    assert suggest(name, known) == expected


def test_an_unknown_key_names_the_closest_and_still_lists_the_known_ones():
    message = _message(lambda: known_keys({"etaa": 1}, ["alpha", "eta", "xi"], "for scene 'hanging'"))
    assert message == "unknown key 'etaa' for scene 'hanging' (did you mean 'eta'?); known keys: alpha, eta, xi"
    message = _message(lambda: known_keys({"zzz": 1}, ["alpha", "eta"], "in the newton settings"))
    assert message == "unknown key 'zzz' in the newton settings; known keys: alpha, eta"


@pytest.mark.parametrize("family, typo, meant", [
    (ForceModel, "variationl", "variational"),
    (Discretisation, "fdd", "fd"),
    (Scheme, "implicit-euer", "implicit-euler"),
    (LineSearch, "armjo", "armijo"),
    (Obstacle, "spher", "sphere"),
    (SceneConfig, "hangin", "hanging"),
])
def test_every_registry_family_suggests(family, typo, meant):
    message = _message(lambda: family.lookup(typo))
    assert f"unknown {family.family} {typo!r} (did you mean {meant!r}?); choose one of " in message
    assert ", ".join(family.names()) in message
    assert "did you mean" not in _message(lambda: family.lookup("qqqqqqqq"))


def test_scene_names_and_fields_from_the_library_and_from_files():
    assert "unknown scene 'hangin' (did you mean 'hanging'?)" in _message(lambda: scenes.config("hangin"))
    assert "did you mean" not in _message(lambda: scenes.config("tablecloth"))
    assert ("unknown key 'etaa' for scene 'hanging' (did you mean 'eta'?); known keys: alpha"
            in _message(lambda: scenes.config("hanging", etaa=1.0)))
    assert ("unknown key 'etaa' in scene file 'a.toml' (did you mean 'eta'?)"
            in _message(lambda: scenes.read_toml_text('scene = "hanging"\netaa = 1\n', "a.toml")))
