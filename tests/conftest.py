"""Shared fixtures of the kernel tests (test_chain, test_hexagon, test_topology).

Import guard: ``python -m pytest`` run from the repository root puts the root on ``sys.path``,
so ``import pyfrustrate`` would find the source tree, which has no compiled ``_kernel``. When
(and only when) that happens, the source tree is dropped from ``sys.path`` so that the installed
package (``pip install .``), which has the extension, is the one under test.
"""
from __future__ import annotations

import importlib
import os
import sys

import numpy as np
import pytest


def _prefer_installed_package():
    try:
        importlib.import_module("pyfrustrate._kernel")
        return
    except ImportError:
        pass
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    sys.path[:] = [p for p in sys.path if os.path.abspath(p or os.curdir) != root]
    for name in [m for m in sys.modules if m == "pyfrustrate" or m.startswith("pyfrustrate.")]:
        del sys.modules[name]
    importlib.invalidate_caches()
    importlib.import_module("pyfrustrate._kernel")  # a clear ImportError if nothing is installed


_prefer_installed_package()


@pytest.fixture
def rng():
    """A fresh, seeded generator per test: failures reproduce."""
    return np.random.default_rng(20250211)


def central_gradient(f, x, h):
    """Central finite-difference gradient of the scalar function ``f`` at ``x`` (step ``h``)."""
    x = np.asarray(x, dtype=float)
    g = np.empty_like(x)
    for i in range(x.size):
        xp, xm = x.copy(), x.copy()
        xp[i] += h
        xm[i] -= h
        g[i] = (f(xp) - f(xm)) / (2 * h)
    return g


@pytest.fixture
def fd_gradient():
    """``fd_gradient(f, x, h)``: central finite differences (O(h^2) truncation error)."""
    return central_gradient
