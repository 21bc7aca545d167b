"""The command line's unknown names get "did you mean" (issue 47, "What must hold"): a scene key, a scene and a
study; one line on stderr, exit code 2, nothing written; a name close to none gets no suggestion."""

import pytest

from validation.commands import main
from validation.studies import get_study


@pytest.mark.parametrize("argv, message", [
    (["run", "hanging", "etaa=1"], "unknown key 'etaa' for scene 'hanging' (did you mean 'eta'?); known keys: alpha"),
    (["run", "hangin"], "unknown scene 'hangin' (did you mean 'hanging'?); choose one of hanging, curtain"),
    (["validate", "tensor"], "unknown study 'tensor' (did you mean 'tensors'?); known: tensors, modes"),
    (["run", "hanging", "--force-model", "variationl"], "unknown force model 'variationl' (did you mean "
                                                         "'variational'?)"),
    (["run", "hanging", "--backend", "fdd"], "unknown backend 'fdd' (did you mean 'fd'?); choose one of fd, fe"),
])
def test_an_unknown_name_is_one_line_with_the_closest_known_one(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err, err
    assert "Traceback" not in err and not any(tmp_path.iterdir())


@pytest.mark.parametrize("argv, message", [
    (["run", "hanging", "qqqq=1"], "unknown key 'qqqq' for scene 'hanging'; known keys: alpha"),
    (["run", "tablecloth"], "unknown scene 'tablecloth'; choose one of hanging"),
    (["validate", "nonsense"], "unknown study 'nonsense'; known: tensors"),
])
def test_a_name_close_to_none_gets_no_suggestion(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err and "did you mean" not in err, err


def test_get_study_suggests():
    with pytest.raises(ValueError, match=r"unknown study 'statik' \(did you mean 'statics'\?\); known: tensors"):
        get_study("statik")
    with pytest.raises(ValueError, match=r"unknown study None; known: tensors"):
        get_study(None)
