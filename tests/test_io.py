"""Workflow outputs are written atomically: a failed write leaves the old file and no debris,
and a finished one is readable like any file the user creates (not private to the writer)."""
import os

import numpy as np
import pytest

from pyfrustrate.io import atomic_path, load_npz, save_npz


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "table.npz"
    save_npz(path, x=np.arange(3))
    with pytest.raises(RuntimeError, match="interrupted"):
        with atomic_path(path) as tmp:
            tmp.write_bytes(b"half a file")
            raise RuntimeError("interrupted")
    np.testing.assert_array_equal(load_npz(path)["x"], np.arange(3))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.npz"]


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_written_file_mode_follows_the_umask(tmp_path, umask):
    previous = os.umask(umask)
    try:
        save_npz(tmp_path / "a.npz", x=np.zeros(2))
        reference = tmp_path / "b"
        reference.write_text("made with open()")
    finally:
        os.umask(previous)
    assert (tmp_path / "a.npz").stat().st_mode & 0o777 == reference.stat().st_mode & 0o777 == 0o666 & ~umask
