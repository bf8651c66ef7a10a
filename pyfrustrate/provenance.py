"""What made a result: recorded in every result file the workflow writes.

``describe`` gives the package version, the git commit of the directory the work runs in and
whether it had uncommitted changes, the hash of the compiled kernel's sources (computed when it
was built, so a stale build shows), the interpreter and numpy versions, and the parameters and
seed of the computation. Nothing in it depends on the time or the machine, so a result computed
twice from the same state is the same file. ``io.save_npz``, ``io.save_json`` and
``plotting.save`` write it; ``io.read_provenance`` reads it back.
"""
from __future__ import annotations

import json
import platform
import subprocess
from collections.abc import Mapping
from importlib import metadata

import numpy as np

from . import _kernel
from .io import json_default

UNKNOWN = "unknown"


def git_state(directory=".") -> tuple[str, bool | None]:
    """The commit of the git checkout holding ``directory``, and whether it has uncommitted changes.

    Parameters
    ----------
    directory : str or Path, optional
        Any directory inside the checkout (default: the working directory).

    Returns
    -------
    commit : str
        ``"unknown"`` outside a checkout (a tarball, an installed copy) or without git.
    dirty : bool or None
        None when unknown.
    """
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=directory, capture_output=True, text=True,
                                timeout=30, check=True).stdout.strip()
        status = subprocess.run(["git", "status", "--porcelain"], cwd=directory, capture_output=True, text=True,
                                timeout=30, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return UNKNOWN, None
    return commit, bool(status.strip())


def package_version() -> str:
    """The installed package's version, or ``"unknown"`` for a source tree never installed.

    Returns
    -------
    str
    """
    try:
        return metadata.version("pyfrustrate")
    except metadata.PackageNotFoundError:  # imported from a source tree that was never installed
        return UNKNOWN


def describe(parameters: Mapping | None = None, *, seed=None, rule: str | None = None, directory=".") -> dict:
    """The provenance record of a computation.

    Parameters
    ----------
    parameters : mapping, optional
        The computation's parameters (converted to JSON types).
    seed : int, optional
        Its seed.
    rule : str, optional
        The workflow rule that ran it.
    directory : str or Path, optional
        Any directory inside the checkout (default: the working directory).
        Where the work runs (its git state is recorded).

    Returns
    -------
    dict
        ``package``, ``version``, ``git_commit``, ``git_dirty``, ``kernel_build_hash``,
        ``python``, ``numpy``, ``rule``, ``parameters``, ``seed``: nothing that depends on the
        time or the machine.

    Raises
    ------
    TypeError
        If a parameter cannot be recorded as JSON.

    Examples
    --------
    >>> from pyfrustrate import provenance
    >>> record = provenance.describe({"ell": 5.0}, seed=1, directory="/")
    >>> record["parameters"], record["seed"], record["git_commit"]
    ({'ell': 5.0}, 1, 'unknown')
    """
    commit, dirty = git_state(directory)
    record = {
        "package": "pyfrustrate",
        "version": package_version(),
        "git_commit": commit,
        "git_dirty": dirty,
        "kernel_build_hash": str(_kernel.build_hash),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "rule": rule,
        "parameters": _builtin(dict(parameters or {})),
        "seed": _builtin(seed),
    }
    json.dumps(record)  # fails here, naming nothing lost, if a parameter cannot be recorded
    return record


def for_job(job) -> dict:
    """The provenance of a Snakemake script job.

    Parameters
    ----------
    job : snakemake.script.Snakemake
        The ``snakemake`` object of a ``script:``.

    Returns
    -------
    dict
        ``describe`` of its rule, its named params and wildcards, and its seed when it has one.
    """
    parameters = dict(job.params.items())
    wildcards = dict(job.wildcards.items())
    if wildcards:
        parameters["wildcards"] = wildcards
    return describe(parameters, seed=parameters.get("seed"), rule=job.rule)


def _builtin(value):
    """JSON-ready: numpy scalars and arrays, tuples and sets become Python numbers and lists."""
    if isinstance(value, Mapping):
        return {str(k): _builtin(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, set, frozenset, range)):
        return [_builtin(v) for v in value]
    if isinstance(value, (np.ndarray, np.generic)):
        return json_default(value)
    if value is None or isinstance(value, (str, int, float, bool)):
        return value
    return str(value)
