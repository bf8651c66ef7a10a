"""The Monte Carlo options' one table (kernel/montecarlo/options.hpp), seen from every side.

Every test iterates the kernel's table (``_kernel.monte_carlo_option_fields``), so a new field is
covered without a new line here: its bad values are refused with a message naming it, by the
kernel's check, by the chain's constructor and by ``MonteCarloOptions``; its boundary values are
accepted or refused as its range says; Python's defaults are the kernel's and reach the chain
unchanged. A few ranges are also pinned by their reason (a probability of 1 that would freeze a
chain), which the table must not lose.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from pyfrustrate import Hexagon, _kernel
from pyfrustrate.montecarlo import MonteCarloOptions
from pyfrustrate.montecarlo.options import KERNEL_OPTION_FIELDS, chain_options

FIELDS = {f["name"]: f for f in KERNEL_OPTION_FIELDS}
RUN_FIELDS = [name for name, f in FIELDS.items() if f["scope"] == "run"]


def bounds(field):
    """(lo, lo excluded, hi, hi excluded) of a real or integer field, read from its range text
    ("a number in [0, 1)", "a finite number > 0", "an integer in [1, 2147483647]")."""
    text = field["range"]
    if field["kind"] == "real" and text == "a finite number":
        return -math.inf, True, math.inf, True
    if text.startswith("a finite number"):
        return float(text.split()[-1]), ">" in text.split()[-2] and "=" not in text.split()[-2], math.inf, True
    inside = text[text.index("in ") + 3:]
    lo, hi = (float(x) for x in inside[1:-1].split(","))
    return lo, inside[0] == "(", hi, inside[-1] == ")"


def bad_values(field):
    """Values the field's kind and range refuse."""
    kind = field["kind"]
    if kind == "flag":
        return ["yes", 1, 0.0, None]
    if kind == "method":
        return ["auto2", "Newton", 2, None]
    lo, lo_open, hi, hi_open = bounds(field)
    values = ["often", None, True]
    if kind == "real":
        values += [math.nan, math.inf, -math.inf]
    else:
        values += [1.5, float(int(lo) + 1), "3", int(lo) - 1]
        if math.isfinite(hi):
            values.append(int(hi) + 1)
    if math.isfinite(lo):
        values.append(lo if lo_open else lo - 0.5 if kind == "real" else int(lo) - 1)
    if math.isfinite(hi):
        values.append(hi if hi_open else hi + 0.5 if kind == "real" else int(hi) + 1)
    return values


def good_values(field):
    """Values the field's range accepts: its closed ends, and a point inside."""
    kind = field["kind"]
    if kind == "flag":
        return [True, False]
    if kind == "method":
        return ["auto", "newton", "lbfgs", "linear"]
    lo, lo_open, hi, hi_open = bounds(field)
    inside = 0.5 * (lo + hi) if math.isfinite(lo + hi) else (lo + 1 if math.isfinite(lo) else 0.25)
    values = [inside if kind == "real" else int(inside)]
    if math.isfinite(lo) and not lo_open:
        values.append(lo if kind == "real" else int(lo))
    if math.isfinite(hi) and not hi_open:
        values.append(hi if kind == "real" else np.int64(hi))  # numpy integers are integers
    return values


@pytest.fixture(scope="module")
def particle():
    return Hexagon.from_continuum(ell=5, nu=0.9, eps=0.01)


BAD = [(name, value) for name, f in FIELDS.items() for value in bad_values(f)]
GOOD = [(name, value) for name, f in FIELDS.items() for value in good_values(f)]


@pytest.mark.parametrize("name, value", BAD, ids=[f"{n}={v!r}" for n, v in BAD])
def test_every_field_refuses_its_bad_values_by_name(particle, name, value):
    message = rf"^{name} must be .*, got "
    with pytest.raises(ValueError, match=message):
        _kernel.check_monte_carlo_options(**{name: value})
    with pytest.raises(ValueError, match=message):
        _kernel.MonteCarlo(particle._kernel_model, 0.01, 4, 2, 0, **{name: value})
    if name in RUN_FIELDS:
        with pytest.raises(ValueError, match=message):
            MonteCarloOptions(**{name: value})
        with pytest.raises(ValueError, match=message):
            MonteCarloOptions().replace(**{name: value})


@pytest.mark.parametrize("name, value", GOOD, ids=[f"{n}={v!r}" for n, v in GOOD])
def test_every_field_takes_the_values_its_range_allows(name, value):
    checked = _kernel.check_monte_carlo_options(**{name: value})[name]
    assert checked == value and type(checked) is {"flag": bool, "real": float, "integer": int, "method": str}[
        FIELDS[name]["kind"]]
    if name in RUN_FIELDS:
        assert getattr(MonteCarloOptions(**{name: value}), name) == value


def test_ranges_keep_their_reasons():
    """Independent of the table: the ends that would break a chain are refused, the others kept."""
    for name in ("bonded_moves", "surface_moves"):  # at 1 a particle could never leave
        with pytest.raises(ValueError, match=name):
            MonteCarloOptions(**{name: 1.0})
    for name in ("cluster_moves", "cluster_link"):
        assert getattr(MonteCarloOptions(**{name: 1.0}), name) == 1.0
    with pytest.raises(ValueError, match="tol"):
        MonteCarloOptions(tol=0.0)
    with pytest.raises(ValueError, match="max_iter"):
        MonteCarloOptions(max_iter=0)
    assert MonteCarloOptions(max_iter=2**31 - 1).max_iter == 2**31 - 1


def test_a_keyword_that_is_no_field_is_a_type_error_naming_it(particle):
    with pytest.raises(TypeError, match="moves_per_sweep"):
        _kernel.check_monte_carlo_options(moves_per_sweep=3)
    with pytest.raises(TypeError, match="moves_per_sweep"):
        _kernel.MonteCarlo(particle._kernel_model, 0.01, 4, 2, 0, moves_per_sweep=3)
    with pytest.raises(TypeError, match="moves_per_sweep"):
        chain_options(None, dict(moves_per_sweep=3))
    with pytest.raises(TypeError):
        _kernel.MonteCarlo(particle._kernel_model, 0.01, 4, 2, 0, "linear")  # options by keyword only


def test_python_defaults_are_the_kernels_and_reach_the_chain_unchanged(particle):
    python = dataclasses.asdict(MonteCarloOptions())
    assert list(python) == RUN_FIELDS
    assert python == {name: FIELDS[name]["default"] for name in RUN_FIELDS}
    assert python == {name: v for name, v in _kernel.check_monte_carlo_options().items() if name in RUN_FIELDS}
    # A chain made with no option at all and one made from MonteCarloOptions() run the same
    # options ('auto' resolved in both), apart from what the particle gives.
    bare = _kernel.MonteCarlo(particle._kernel_model, 0.01, 6, 5, 0).options
    from_python = _kernel.MonteCarlo(particle._kernel_model, 0.01, 6, 5, 0,
                                     **MonteCarloOptions().kernel_arguments(particle)).options
    assert set(bare) == set(FIELDS) and bare["method"] == from_python["method"] == "newton"
    assert {k: bare[k] for k in RUN_FIELDS} == {k: from_python[k] for k in RUN_FIELDS}
    assert from_python["force_scale"] == particle.force_scale and bare["force_scale"] == 1.0
    # The measured defaults, which the anneal docstring states (options.DEFAULTS_MEASURED).
    assert (python["cluster_moves"], python["cluster_link"], python["bonded_moves"], python["surface_moves"]) == \
        (0.05, 0.9, 0.5, 0.2)


def test_the_chain_runs_what_it_was_given(particle):
    options = MonteCarloOptions(method="lbfgs", tol=1e-4, cluster_moves=0.3, cluster_link=0.6, bonded_moves=0.1,
                                surface_moves=0.0, cache=False, delayed_acceptance=False, max_iter=500)
    chain = _kernel.MonteCarlo(particle._kernel_model, 0.01, 6, 5, 0, **options.kernel_arguments(particle)).options
    assert {k: chain[k] for k in RUN_FIELDS} == dataclasses.asdict(options)
    assert chain["parent_start"] is False  # warm starts of L-BFGS are from the linear solution


def test_the_documentation_lists_every_field(particle):
    kernel_doc = type(_kernel.MonteCarlo(particle._kernel_model, 0.01, 4, 2, 0)).__init__.__doc__
    for name, f in FIELDS.items():
        assert f"{name} ({f['range']}, default " in kernel_doc
        if name in RUN_FIELDS:
            assert f"    {name} : " in MonteCarloOptions.__doc__
    assert "force_scale : " not in MonteCarloOptions.__doc__  # the particle gives it


def test_every_counter_is_documented_once_with_a_meaning(particle):
    """The ``counters`` docstring is written from the counters' own table: each counter a chain
    reports has exactly one line with a non-empty meaning, and no line names a counter the chain
    does not report (a family whose ``for_each`` forgot a meaning, or a hand-written list gone
    stale, fails here)."""
    chain = _kernel.MonteCarlo(particle._kernel_model, 0.01, 4, 2, 0)
    documented = {}
    for line in type(chain).counters.__doc__.splitlines():
        if line.startswith("- ``"):
            name, meaning = line[4:].split("``: ", 1)
            assert name not in documented and meaning.strip()
            documented[name] = meaning
    assert set(documented) == set(chain.counters)


def test_the_defaults_point_to_files_that_exist():
    """``DEFAULTS_MEASURED`` names where the defaults were measured; every file it names must be
    in the repository (it pointed into a README section long after the README lost it)."""
    from pathlib import Path

    from pyfrustrate.montecarlo import DEFAULTS_MEASURED

    root = Path(__file__).resolve().parents[1]
    for entry in DEFAULTS_MEASURED.split(", "):
        assert (root / entry.split(" (")[0]).is_file(), entry
