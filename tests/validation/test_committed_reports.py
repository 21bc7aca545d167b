"""The committed reports: every CSV reads back with numeric columns where its values are numbers."""

from pathlib import Path

import pandas as pd
import pytest

REPORTS = Path(__file__).resolve().parents[2] / "reports"
CSVS = sorted(REPORTS.rglob("*.csv"))


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def test_there_are_committed_reports_to_check():
    assert len(CSVS) >= 20, f"only {len(CSVS)} CSV files under {REPORTS}"


@pytest.mark.parametrize("path", CSVS, ids=[str(p.relative_to(REPORTS)) for p in CSVS])
def test_a_column_of_numbers_reads_as_numbers(path):
    frame = pd.read_csv(path)
    raw = pd.read_csv(path, dtype=str, keep_default_na=False)
    assert len(frame) > 0, f"{path} has no rows"
    for column in raw.columns:
        cells = [c for c in raw[column] if c != ""]
        if cells and all(_numeric(c) for c in cells):
            assert frame[column].dtype.kind in "if", f"{path.name}: column {column!r} reads as {frame[column].dtype}"
        assert not any(c.startswith("np.") for c in cells), f"{path.name}: column {column!r} holds numpy reprs"
