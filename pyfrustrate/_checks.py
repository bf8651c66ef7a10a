"""Checks of scalar arguments shared by the public functions: each returns the value converted,
or raises ``ValueError`` naming the parameter (never a ``TypeError`` from a conversion, never a
silent truncation of 2.5 to 2)."""
from __future__ import annotations

import math
from numbers import Integral


def integer(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int in ``[lo, hi]``.

    Python and numpy integers only: a float, even 2.0, is refused, as are booleans.

    Parameters
    ----------
    name : str
        The parameter's name, quoted in the message.
    value : object
        What the caller passed.
    lo : int
        Smallest allowed value.
    hi : int, optional
        Largest allowed value (None: no upper bound).

    Returns
    -------
    int

    Raises
    ------
    ValueError
        If ``value`` is not an integer in range.
    """
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = int(value)
    if value < lo or (hi is not None and value > hi):
        bound = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise ValueError(f"{name} must be {bound}, got {value}")
    return value


def non_negative(name: str, value) -> float:
    """``value`` as a finite float ``>= 0`` (temperatures, binding energy, lengths).

    Parameters
    ----------
    name : str
        The parameter's name, quoted in the message.
    value : object
        What the caller passed.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``value`` is not a finite non-negative number.
    """
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(t) or t < 0:
        raise ValueError(f"{name} must be non-negative and finite, got {value!r}")
    return t


def probability(name: str, value) -> float:
    """``value`` as a float in [0, 1].

    Parameters
    ----------
    name : str
        The parameter's name, quoted in the message.
    value : object
        What the caller passed.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``value`` is not a number in [0, 1].
    """
    try:
        p = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number in [0, 1], got {value!r}") from None
    if not 0.0 <= p <= 1.0:  # NaN fails too
        raise ValueError(f"{name} must lie in [0, 1], got {value!r}")
    return p


def particle(name: str, value):
    """``value`` itself if it is a particle model, else ``TypeError`` naming the parameter.

    A particle model carries the kernel's evaluator (``_kernel_model``) and its ``tiling``
    (``pyfrustrate.particles.Particle``). Every entry point that takes a particle calls this, so
    the same mistake (a topology, a number or ``None`` where the particle goes) raises the same
    exception everywhere, before any work.

    Parameters
    ----------
    name : str
        The parameter's name, quoted in the message.
    value : object
        What the caller passed.

    Returns
    -------
    object
        ``value`` unchanged.

    Raises
    ------
    TypeError
        If ``value`` is not a particle model.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, topology
    >>> from pyfrustrate._checks import particle
    >>> particle("particle", Hexagon.from_continuum(ell=2, nu=0.5)).tiling
    'hexagon'
    >>> particle("particle", topology.disk(1))
    Traceback (most recent call last):
    ...
    TypeError: particle must be a particle model (Hexagon, Triangle, RandomHexagon), got a Topology
    """
    if getattr(value, "_kernel_model", None) is None or not hasattr(value, "tiling"):
        shown = repr(value)
        shown = shown if len(shown) <= 80 else f"a {type(value).__name__}"  # not a whole array of sites
        raise TypeError(f"{name} must be a particle model (Hexagon, Triangle, RandomHexagon), got {shown}")
    return value


#: Largest share of the machine's physical memory one request may ask for: beyond it a request
#: is refused up front rather than left to thrash the machine or die in numpy's allocator.
MEMORY_FRACTION = 0.5


def physical_memory() -> int | None:
    """The machine's physical memory (``os.sysconf``).

    Returns
    -------
    int or None
        Bytes; None where the system does not report it.
    """
    import os

    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def byte_count(n_bytes: float) -> str:
    """A number of bytes in binary units, three significant figures.

    Parameters
    ----------
    n_bytes : float
        A number of bytes (a float: estimates may exceed any integer type).

    Returns
    -------
    str

    Examples
    --------
    >>> from pyfrustrate._checks import byte_count
    >>> byte_count(512), byte_count(2.84 * 2**50)
    ('512 B', '2.84 PiB')
    """
    value, unit = float(n_bytes), "B"
    for next_unit in ("KiB", "MiB", "GiB", "TiB", "PiB", "EiB", "ZiB", "YiB"):
        if value < 1024:
            break
        value, unit = value / 1024, next_unit
    return f"{value:.3g} {unit}"


def affordable(request: str, n_bytes: float) -> None:
    """Refuse, with ``ValueError``, a request whose estimated memory ``n_bytes`` exceeds
    ``MEMORY_FRACTION`` of the machine's physical memory; the message quotes both figures.

    Call it with an estimate computed from the request's sizes alone, before allocating anything.

    Parameters
    ----------
    request : str
        The request as the user wrote it, e.g. ``"disk(R=10000000)"``, quoted in the message.
    n_bytes : float
        Estimated peak memory of the request, in bytes (may exceed any integer type: a float).

    Raises
    ------
    ValueError
        If ``n_bytes`` is above the allowed share of physical memory.

    Examples
    --------
    >>> from pyfrustrate._checks import affordable
    >>> affordable("a small request", 1e6)
    >>> affordable("a huge request", 2.84 * 2**50)
    Traceback (most recent call last):
    ...
    ValueError: a huge request would need about 2.84 PiB of memory; ...
    """
    memory = physical_memory()
    limit = MEMORY_FRACTION * memory if memory else 2.0**63  # unknown machine: refuse only the absurd
    if not n_bytes <= limit:
        have = f"this machine has {byte_count(memory)}" if memory else "more than any machine has"
        raise ValueError(f"{request} would need about {byte_count(n_bytes)} of memory; {have}, and one request "
                         f"may use at most {MEMORY_FRACTION:.0%} of it")
