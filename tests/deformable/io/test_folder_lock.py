"""The run folder's lock is an OS lock (filelock): held while a run owns the folder, released by the OS when the
run dies, so no test of whether a process lives is needed (issue 47, point 6)."""

import inspect
import os
import socket
import threading

import pytest

from deformable.errors import OutputFolderError
from deformable.io import folder as folder_module
from deformable.io.folder import LOCK, RunFolder, held


def test_a_claimed_folder_is_held_and_a_second_claim_is_refused_in_one_line(tmp_path):
    out = tmp_path / "out"
    assert held(out) is None
    with RunFolder(out):
        owner = f"pid {os.getpid()} on {socket.gethostname()}"
        assert held(out) == owner
        for _ in range(2):  # a refused claim leaves the owner's line as it was
            with pytest.raises(OutputFolderError, match="is in use by another run") as err:
                RunFolder(out, overwrite=True).claim()
            assert owner in str(err.value) and "\n" not in str(err.value)
    assert not (out / LOCK).exists() and held(out) is None
    assert RunFolder(out).claim() == out


def test_check_writes_nothing_and_a_lock_file_nobody_holds_is_free(tmp_path, caplog):
    out = tmp_path / "out"
    out.mkdir()
    assert RunFolder(out).check() is False and list(out.iterdir()) == []
    (out / LOCK).write_text("1 elsewhere\n")  # left by a killed run: its OS lock went with it
    assert held(out) is None
    folder = RunFolder(out)
    folder.claim()
    assert "cleared the stale lock" in caplog.text and "pid 1 on elsewhere" in caplog.text
    assert (out / LOCK).read_text().split()[0] == str(os.getpid())
    folder.release()
    assert not (out / LOCK).exists()


def test_the_lock_is_the_runs_not_the_threads(tmp_path):
    """Released from another thread than the one that took it (a run's threads share its lock)."""
    folder = RunFolder(tmp_path / "out")
    folder.claim()
    thread = threading.Thread(target=folder.release)
    thread.start()
    thread.join()
    assert held(tmp_path / "out") is None and not (tmp_path / "out" / LOCK).exists()


def test_no_process_table_is_read():
    source = inspect.getsource(folder_module)
    assert "/proc" not in source and "os.kill" not in source
