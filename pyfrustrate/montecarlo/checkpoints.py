"""Checkpoints of Monte Carlo runs: files that hold data only, safe to load from anywhere.

A checkpoint is one ``.npz`` archive (``numpy.savez``, read back with ``allow_pickle=False``): the
arrays of the run's state (sites, traces) and one entry ``metadata``, a JSON text holding the
format name and ``FORMAT_VERSION``, the kind of run (``"anneal"``, ``"replica_exchange"``), the
run's signature (every parameter that defines its chain: a checkpoint of another run is refused),
and the scalars of the state (random generator states as text, running energies, counters). No
object is ever unpickled, so a crafted file cannot run code; every file that is not a checkpoint
of this run (empty, truncated, garbage, a pickle, another version or another run) is refused
with a ``ValueError`` that names it and says what to do. Files are written atomically
(``io.atomic_path``).
"""
from __future__ import annotations

import json
import os
import zipfile
from typing import Any

import numpy as np

from ..io import json_default, atomic_path

__all__ = ["FORMAT", "FORMAT_VERSION", "write_checkpoint", "read_checkpoint_file", "json_normalised"]

FORMAT = "pyfrustrate Monte Carlo checkpoint"
#: Version 1 was a pickle (refused: unpickling a file can run code); version 2 this archive.
FORMAT_VERSION = 2
_METADATA = "metadata"


def json_normalised(value):
    """``value`` as it reads back from JSON: the form in which signatures are compared.

    Parameters
    ----------
    value : object
        JSON-serialisable, numpy scalars and arrays allowed.

    Returns
    -------
    object
        Tuples as lists, numpy scalars as Python numbers.

    Examples
    --------
    >>> import numpy as np
    >>> from pyfrustrate.montecarlo.checkpoints import json_normalised
    >>> json_normalised({"box": np.int64(6), "pair": (1, 2)})
    {'box': 6, 'pair': [1, 2]}
    """
    return json.loads(json.dumps(value, default=json_default))


def _refused(path, reason: str) -> ValueError:
    return ValueError(f"checkpoint: {os.fspath(path)!r} {reason}; delete it or pass another checkpoint path to start the "
                      "run afresh")


def write_checkpoint(path, kind: str, signature: dict, metadata: dict, arrays: dict) -> None:
    """Write a checkpoint of a run of ``kind`` atomically.

    Parameters
    ----------
    path : str or path-like
        The file (an ``.npz`` archive; replaced atomically).
    kind : str
        The kind of run (``"anneal"``, ``"replica_exchange"``).
    signature : dict
        The run's defining parameters.
    metadata : dict
        JSON-serialisable scalars, lists and dicts of the state.
    arrays : dict
        Numeric numpy arrays of the state.

    Raises
    ------
    TypeError
        An array that is not numeric (it could not be read back without unpickling).
    """
    header = dict(format=FORMAT, version=FORMAT_VERSION, kind=kind, signature=signature, state=metadata)
    entries: dict[str, Any] = {name: np.asarray(a) for name, a in arrays.items()}
    for name, a in entries.items():
        if a.dtype.kind not in "biuf":
            raise TypeError(f"checkpoint array {name!r} must be numeric, got dtype {a.dtype}")
    entries[_METADATA] = np.array(json.dumps(header, default=json_default))
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **entries)
        f.flush()
        os.fsync(f.fileno())


def read_checkpoint_file(path, kind: str, signature: dict | None = None) -> tuple[dict, dict]:
    """``(metadata, arrays)`` of the checkpoint at ``path`` written by a run of ``kind``.

    Nothing in the file is executed.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file.
    kind : str
        The kind of run expected.
    signature : dict or None, optional
        The run's defining parameters: refused unless the run that wrote the file had the same
        ones (the differing parameters are named). None accepts any run of ``kind``.

    Returns
    -------
    tuple of (dict, dict)
        The state's metadata (with the file's ``signature``) and its arrays.

    Raises
    ------
    FileNotFoundError
        No file at ``path``.
    ValueError
        A file that is not a checkpoint of this kind (and signature), naming it.
    """
    try:
        archive = np.load(path, allow_pickle=False)
        if not hasattr(archive, "files"):  # a bare .npy array
            raise _refused(path, "is not a checkpoint archive (a bare array)")
        with archive:
            arrays = {name: archive[name] for name in archive.files}
    except FileNotFoundError:
        raise
    except ValueError as e:
        if str(e).startswith("checkpoint:"):
            raise
        # numpy's refusal of pickled data, of object arrays, or of a file it cannot parse.
        raise _refused(path, f"is not a checkpoint archive ({e})") from None
    except (OSError, EOFError, zipfile.BadZipFile, KeyError) as e:
        raise _refused(path, f"is unreadable, empty or truncated ({type(e).__name__}: {e})") from None
    text = arrays.pop(_METADATA, None)
    if text is None or text.dtype.kind != "U" or text.ndim != 0:
        raise _refused(path, "holds no checkpoint metadata")
    try:
        header = json.loads(str(text))
    except json.JSONDecodeError as e:
        raise _refused(path, f"has corrupt metadata ({e})") from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise _refused(path, f"is not a {FORMAT}")
    if header.get("version") != FORMAT_VERSION:
        raise _refused(path, f"was written in checkpoint format version {header.get('version')!r}, this pyfrustrate "
                             f"reads version {FORMAT_VERSION}")
    if header.get("kind") != kind:
        raise _refused(path, f"is a checkpoint of {header.get('kind')!r}, not of {kind!r}")
    state = header.get("state")
    if not isinstance(state, dict) or not isinstance(header.get("signature"), dict):
        raise _refused(path, "has incomplete metadata")
    if signature is not None:
        saved, current = header["signature"], json_normalised(signature)
        differ = sorted(k for k in set(saved) | set(current) if saved.get(k) != current.get(k))
        if differ:
            raise _refused(path, f"was written by a run with different parameters ({', '.join(differ)})")
    return dict(state, signature=header["signature"]), arrays
