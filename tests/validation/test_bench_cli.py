"""``deformable bench``: the table and CSV of step time against one direct factor+solve."""

import csv

import pytest

from validation.cli import main


def test_bench_writes_the_table_and_csv(tmp_path, capsys):
    assert main(["bench", "--sizes", "8,12", "--steps", "2", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "step / (factor+solve)" in out and "| fd | 12x12 |" in out
    rows = list(csv.DictReader((tmp_path / "bench.csv").open()))
    assert [r["nodes"] for r in rows] == ["8x8", "12x12"]
    for r in rows:
        parts = float(r["assembly"]) + float(r["factorisation"]) + float(r["solve"])
        assert 0 < parts <= float(r["step"]) * 1.01
        ref = float(r["direct_factor"]) + float(r["direct_solve"])
        assert float(r["ratio"]) == pytest.approx(float(r["step"]) / ref, rel=1e-3)


@pytest.mark.parametrize("argv, message", [
    (["--sizes", "8,x"], "--sizes must be comma-separated integers"),
    (["--sizes", "2"], "grid sizes of at least 3"),
    (["--backend", "fv"], "unknown backend 'fv'"),
    (["--steps", "0"], "--steps must be a positive integer"),
])
def test_bench_bad_input(argv, message, tmp_path, capsys):
    assert main(["bench", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err
    assert not (tmp_path / "o").exists()
