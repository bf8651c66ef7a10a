"""Atomic result files: nothing half-written survives an interrupted run.

Every writer goes to a temporary file in the target's directory and renames it into place
(``os.replace`` is atomic on POSIX), so a result file is either complete or absent. Writers take
a ``provenance`` record (``pyfrustrate.provenance``) and store it with the result, where
``read_provenance`` finds it: an ``.npz`` entry, a ``.json`` key, a ``.csv`` first comment line,
a PNG text chunk, a PDF's Subject field (all under the name PROVENANCE_KEY).
"""
from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import tempfile
import threading
from pathlib import Path

import numpy as np


@contextlib.contextmanager
def atomic_path(path, suffix: str = ""):
    """A temporary path beside ``path``, moved onto ``path`` if the block succeeds (context manager).

    Parameters
    ----------
    path : str or Path
        The target; its directory is created.
    suffix : str, optional
        Suffix of the temporary file (default: the target's).

    Yields
    ------
    Path
        Where to write; removed if the block raises.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from pyfrustrate.io import atomic_path
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "result.txt"
    >>> with atomic_path(target) as tmp:
    ...     _ = tmp.write_text("done")
    >>> target.read_text()
    'done'
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix or path.suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        # mkstemp makes the file private (0600); results and figures get the usual mode.
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


PROVENANCE_KEY = "provenance"


def save_npz(path, *, provenance: dict | None = None, **arrays) -> None:
    """Atomically write a compressed ``.npz`` of named arrays.

    Parameters
    ----------
    path : str or Path
        The target.
    provenance : dict, optional
        Stored as a JSON string under ``PROVENANCE_KEY`` (``provenance.describe``).
    **arrays
        The arrays, by name.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from pyfrustrate import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "a.npz"
    >>> io.save_npz(path, provenance={"seed": 1}, x=[1, 2])
    >>> io.load_npz(path)["x"].tolist(), io.read_provenance(path)
    ([1, 2], {'seed': 1})
    """
    if provenance is not None:
        arrays[PROVENANCE_KEY] = np.array(json.dumps(provenance, sort_keys=True, default=json_default))
    with atomic_path(path, ".npz") as tmp:
        np.savez_compressed(tmp, **arrays)


def load_npz(path) -> dict:
    """Read an ``.npz`` written by ``save_npz`` into a plain dict of arrays (without the provenance
    record: ``read_provenance`` reads that).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    dict of ndarray
    """
    with np.load(path, allow_pickle=False) as data:
        return {k: data[k] for k in data.files if k != PROVENANCE_KEY}


def save_json(path, obj, *, provenance: dict | None = None) -> None:
    """Atomically write ``obj`` as indented JSON.

    Parameters
    ----------
    path : str or Path
        The target.
    obj : object
        JSON-serialisable (numpy scalars and arrays are converted).
    provenance : dict, optional
        Stored under ``PROVENANCE_KEY``; ``obj`` must then be a dict without that key.

    Raises
    ------
    ValueError
        If a provenance record cannot be added to ``obj``.
    """
    if provenance is not None:
        if not isinstance(obj, dict) or PROVENANCE_KEY in obj:
            raise ValueError(f"save_json: a provenance record needs a dict without a '{PROVENANCE_KEY}' key")
        obj = {**obj, PROVENANCE_KEY: provenance}
    with atomic_path(path, ".json") as tmp:
        tmp.write_text(json.dumps(obj, indent=2, sort_keys=True, default=json_default) + "\n")


def provenance_line(provenance: dict) -> str:
    """The first line of a CSV result: a comment holding the provenance record.

    Parameters
    ----------
    provenance : dict
        A provenance record (``provenance.describe``).

    Returns
    -------
    str
        Ending in a newline.
    """
    return f"# {PROVENANCE_KEY}: {json.dumps(provenance, sort_keys=True, default=json_default)}\n"


def read_provenance(path) -> dict | None:
    """The provenance record stored with a result file.

    Parameters
    ----------
    path : str or Path
        A ``.npz``, ``.json``, ``.csv`` or ``.png`` file.

    Returns
    -------
    dict or None
        None when the file has none.

    Raises
    ------
    ValueError
        For another suffix.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npz":
        with np.load(path, allow_pickle=False) as data:
            return json.loads(str(data[PROVENANCE_KEY])) if PROVENANCE_KEY in data.files else None
    if suffix == ".json":
        obj = json.loads(path.read_text())
        return obj.get(PROVENANCE_KEY) if isinstance(obj, dict) else None
    if suffix == ".csv":
        first = path.read_text().split("\n", 1)[0]
        prefix = f"# {PROVENANCE_KEY}: "
        return json.loads(first[len(prefix):]) if first.startswith(prefix) else None
    if suffix == ".png":
        from PIL import Image  # matplotlib's own dependency

        with Image.open(path) as image:
            text = image.text.get(PROVENANCE_KEY)
        return json.loads(text) if text else None
    raise ValueError(f"read_provenance: no provenance is stored in '{suffix}' files ({path})")


def json_default(value):
    """The ``default=`` of ``json.dumps`` for numpy values: a numpy scalar as its Python value, an
    array as nested lists.

    Parameters
    ----------
    value : object
        What ``json`` cannot serialise by itself.

    Returns
    -------
    int, float, bool, str or list

    Raises
    ------
    TypeError
        Anything else, named by its type.

    Examples
    --------
    >>> import json, numpy as np
    >>> from pyfrustrate.io import json_default
    >>> json.dumps({"n": np.int64(3), "x": np.array([0.5, 1.0])}, default=json_default)
    '{"n": 3, "x": [0.5, 1.0]}'
    """
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot serialise {type(value).__name__}")


@contextlib.contextmanager
def sigterm_raises():
    """Within the block, SIGTERM raises ``SystemExit`` instead of ending the process on the spot
    (context manager).

    SIGTERM is how Snakemake cancels its jobs, a scheduler pre-empts one, or a plain ``kill``
    stops one; raising lets ``except`` and ``finally`` blocks run: an annealing run saves its
    checkpoint before it stops. Only the main thread can handle signals; elsewhere the block runs
    unchanged.

    Yields
    ------
    None
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum, frame):
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def logging_to(path):
    """Send stdout and stderr of a workflow script to its ``log:`` file (context manager).

    Parameters
    ----------
    path : str or Path or None
        The log file; None leaves the streams alone.

    Yields
    ------
    None
    """
    if path is None:
        yield
        return
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as log, contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
        try:
            yield
        except BaseException:
            import traceback

            traceback.print_exc(file=log)
            raise
        finally:
            sys.stdout.flush()
