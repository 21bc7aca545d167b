"""The case runner (validation.harness.runner): serial and process-pool maps agree."""

import os

import pytest

from validation.harness.runner import Runner


def square_and_pid(x):
    return x * x, os.getpid()


def test_a_pool_maps_in_order_like_the_serial_runner():
    serial = Runner(1).map(square_and_pid, range(6))
    with Runner(2) as runner:
        pooled = runner.map(square_and_pid, range(6))
    assert [v for v, _ in pooled] == [v for v, _ in serial] == [x * x for x in range(6)]
    assert {pid for _, pid in serial} == {os.getpid()}
    assert os.getpid() not in {pid for _, pid in pooled}


@pytest.mark.parametrize("jobs", [0, -1, 1.5, True])
def test_jobs_must_be_a_positive_integer(jobs):
    with pytest.raises(ValueError, match="jobs must be a positive integer"):
        Runner(jobs)
