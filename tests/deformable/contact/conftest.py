"""Fixtures of the contact tests."""

import ipctk
import pytest


@pytest.fixture
def one_thread():
    """The IPC Toolkit on one thread: on more its sums over the pairs run in a varying order, and two calls at the
    same state may differ in the last bits (measured on 2 threads: 2 energies, 5 gradients out of 50 calls; a run
    resumed from a checkpoint then ends 6.5e-16 m from the whole run's, not on it)."""
    threads = ipctk.get_num_threads()
    ipctk.set_num_threads(1)
    yield
    ipctk.set_num_threads(threads)
