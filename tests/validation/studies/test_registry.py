"""The registry of studies (validation.studies): every study, in the order ``deformable validate`` runs them."""

import pytest

from validation.studies import STUDIES, get_study


def test_registry_holds_every_study_in_order():
    assert list(STUDIES) == ["tensors", "modes", "statics", "cross", "time", "compatibility", "work", "variational",
                             "paper", "contact", "shells", "fabrics"]
    assert not STUDIES["paper"].in_default  # its sweep runs on its own: deformable validate paper
    assert not STUDIES["cross"].in_default  # minutes of FE motions: deformable validate cross
    assert not STUDIES["contact"].in_default  # minutes of contact runs: deformable validate contact
    assert not STUDIES["shells"].in_default  # issue 28's problems: deformable validate shells
    assert all(get_study(name) is study for name, study in STUDIES.items())
    with pytest.raises(ValueError, match="unknown study 'nope'; known: tensors"):
        get_study("nope")
