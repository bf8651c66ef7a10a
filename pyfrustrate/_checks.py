"""Checks of scalar arguments shared by the public functions: each returns the value converted,
or raises ``ValueError`` naming the parameter (never a ``TypeError`` from a conversion, never a
silent truncation of 2.5 to 2)."""
from __future__ import annotations

import math
from numbers import Integral


def integer(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int in ``[lo, hi]`` (``hi`` None: no upper bound). Python and numpy
    integers only: a float, even 2.0, is refused, as are booleans."""
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if value < lo or (hi is not None and value > hi):
        bound = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise ValueError(f"{name} must be {bound}, got {value}")
    return value


def non_negative(name: str, value) -> float:
    """``value`` as a finite float >= 0 (temperatures, binding energy, lengths)."""
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(t) or t < 0:
        raise ValueError(f"{name} must be non-negative and finite, got {value!r}")
    return t


def probability(name: str, value) -> float:
    """``value`` as a float in [0, 1]."""
    try:
        p = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number in [0, 1], got {value!r}") from None
    if not 0.0 <= p <= 1.0:  # NaN fails too
        raise ValueError(f"{name} must lie in [0, 1], got {value!r}")
    return p
