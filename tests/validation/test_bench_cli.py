"""``deformable bench``: the table and CSV of step time against one direct factor+solve."""

import csv

import pytest

from validation.cli import main


def test_bench_writes_the_table_and_csv(tmp_path, capsys):
    assert main(["bench", "--sizes", "8,12", "--steps", "2", "--variational-sizes", "6", "--out",
                 str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "step / (factor+solve)" in out and "| fd | 12x12 |" in out
    with (tmp_path / "bench.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [r["nodes"] for r in rows] == ["8x8", "12x12"]
    for r in rows:
        parts = float(r["assembly"]) + float(r["factorisation"]) + float(r["solve"])
        assert 0 < parts <= float(r["step"]) * 1.01
        ref = float(r["direct_factor"]) + float(r["direct_solve"])
        assert float(r["ratio"]) == pytest.approx(float(r["step"]) / ref, rel=1e-3)
    with (tmp_path / "bench_variational.csv").open() as fh:
        (variational,) = list(csv.DictReader(fh))
    assert variational["nodes"] == "6x6" and float(variational["newton_per_step"]) >= 1
    assert "Newton iterations / step" in out


@pytest.mark.parametrize("argv, message", [
    (["--sizes", "8,x"], "--sizes must be comma-separated integers"),
    (["--sizes", "2"], "grid sizes of at least 3"),
    (["--backend", "fv"], "unknown backend 'fv'"),
    (["--steps", "0"], "--steps must be a positive integer"),
    (["--variational-sizes", "4,y"], "--variational-sizes must be comma-separated integers"),
])
def test_bench_bad_input(argv, message, tmp_path, capsys):
    assert main(["bench", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not (tmp_path / "o").exists()
