"""The Examples sections of the docstrings run, as doctests, against the installed package.

Every module of the package is searched (the docstrings a user reads with ``help``), so an example
that drifts from the code fails here. Numbers in examples are printed rounded, so that the last
digits of a minimiser or of a platform's libm cannot break them.
"""
from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import pyfrustrate as pf

MODULES = ["pyfrustrate"] + sorted(info.name for info in pkgutil.walk_packages(pf.__path__, prefix="pyfrustrate.")
                                   if info.name != "pyfrustrate._kernel")
FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS

#: The main entry points, each of which must carry an Examples section that runs (issue 34).
ENTRY_POINTS = [
    "pyfrustrate.relaxation.relax", "pyfrustrate.particles.Hexagon.from_continuum", "pyfrustrate.particles.Triangle",
    "pyfrustrate.topology.disk", "pyfrustrate.topology.fiber", "pyfrustrate.topology.bulk",
    "pyfrustrate.topology.fiber_axis", "pyfrustrate.continuum.optimal_width", "pyfrustrate.continuum.optimal_radius",
    "pyfrustrate.continuum.phase", "pyfrustrate.continuum.fiber_energy", "pyfrustrate.continuum.disk_energy",
    "pyfrustrate.continuum.particle_parameters", "pyfrustrate.ansatz.catalogue", "pyfrustrate.ansatz.relax_catalogue",
    "pyfrustrate.ansatz.CatalogueEnergies.winners", "pyfrustrate.ansatz.finite_aggregates", "pyfrustrate.chain.relax",
    "pyfrustrate.random_particles.RandomHexagon", "pyfrustrate.random_particles.sample_properties",
    "pyfrustrate.random_particles.boundary_layer_length", "pyfrustrate.relaxation.particle_energies",
    "pyfrustrate.relaxation.relaxed_drawing",
]


def resolve(dotted: str):
    module_name, _, rest = dotted.partition(".")
    obj = importlib.import_module(module_name)
    path = module_name
    for part in rest.split("."):
        path += "." + part
        try:
            obj = importlib.import_module(path)
        except ImportError:
            obj = getattr(obj, part)
    return obj


@pytest.mark.parametrize("name", MODULES)
def test_examples_of_module_run(name):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    tests = finder.find(module, name, globs={})
    for test in tests:
        runner.run(test)
    assert runner.failures == 0, f"{runner.failures} example(s) failed in {name} (output above)"


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_entry_point_has_a_running_example(name):
    obj = resolve(name)
    doc = obj.__doc__ or ""
    assert "Examples\n" in doc and "--------" in doc.split("Examples\n", 1)[1][:40], f"{name}: no Examples section"
    examples = doctest.DocTestParser().get_examples(doc)
    assert examples, f"{name}: the Examples section holds no doctest"
