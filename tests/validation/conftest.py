"""What the executor tests share: one Dask LocalCluster of 2 workers, 1 thread each, for the session."""

import distributed
import pytest

from validation.harness.runner import Runner


@pytest.fixture(scope="session")
def dask_scheduler(tmp_path_factory):
    """(address, scheduler file) of a LocalCluster(n_workers=2, threads_per_worker=1) started by ``local:2``.

    The cluster is the one ``--scheduler local:2`` starts (:class:`Runner`); the scheduler file is written
    by Dask (``Client.write_scheduler_file``), as ``dask scheduler --scheduler-file`` would.
    """
    path = tmp_path_factory.mktemp("dask") / "scheduler.json"
    with Runner(scheduler="local:2") as runner:
        with distributed.Client(runner.address) as client:
            client.write_scheduler_file(str(path))
        yield runner.address, path
