"""``deformable validate``: bad input is one line and exit code 2; a small run writes its report."""

import pytest

from validation.commands import main


@pytest.mark.parametrize("argv, message", [
    (["validate", "nope"], "unknown study 'nope'"),
    (["validate", "tensors", "--surfaces", "plane,blob"], "unknown surface 'blob'"),
    (["validate", "statics", "--levels", "99"], "study 'statics' runs 3 to 7 levels, got 99"),
    (["validate", "statics", "--levels", "1"], "runs 3 to 7 levels, got 1"),
    (["validate", "--jobs", "0", "statics"], "jobs must be a positive integer"),
    (["validate", "--quick", "--full"], "not allowed with argument"),
    (["validate", "statics", "--scheduler", "local:0"], "needs a positive number of workers"),
    (["validate", "statics", "--jobs", "2", "--scheduler", "local:2"], "not allowed with argument"),
])
def test_bad_input_is_one_line_and_exit_2(argv, message, capsys, tmp_path):
    code = main(argv + ["--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not any(tmp_path.iterdir()), "nothing may be written on bad input"


def test_a_small_run_writes_its_folder_and_the_index(capsys, tmp_path):
    code = main(["validate", "statics", "--levels", "3", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0, out
    assert (tmp_path / "statics" / "summary.md").is_file() and (tmp_path / "index.md").is_file()
    assert "checks passed, 0 failed" in out


def test_unwritable_output_folder_is_one_line_before_any_work(capsys, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    code = main(["validate", "statics", "--out", str(blocker / "reports")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "cannot write to output folder" in err


def test_each_studys_line_is_printed_as_it_finishes_not_at_the_end(capsys, tmp_path, monkeypatch):
    """A log (stdout a file) has a study's line once that study is written, before the next one starts."""
    import validation.commands.validate as validate

    seen = []
    real = validate.write_study

    def write_study(res, out):
        real(res, out)
        seen.append(capsys.readouterr().out)  # stdout up to the moment this study's report is written

    monkeypatch.setattr(validate, "write_study", write_study)
    real_index = validate.write_index
    monkeypatch.setattr(validate, "write_index", lambda *a: seen.append(capsys.readouterr().out) or real_index(*a))
    assert main(["validate", "statics", "compatibility", "--levels", "3", "--out", str(tmp_path)]) == 0
    # after the first study's report, nothing yet; the first study's line is out before the second is written
    assert "statics" not in seen[0] and seen[1].startswith("statics ") and "passed" in seen[1]
    assert seen[2].startswith("compatibility ")
