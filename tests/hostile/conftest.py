"""The hostile tests see a machine with 1 GB of memory available, so that "beyond memory" is the same everywhere."""

import pytest


@pytest.fixture(autouse=True)
def one_gigabyte(monkeypatch):
    monkeypatch.setattr("deformable.limits.available_memory", lambda: 1e9)
