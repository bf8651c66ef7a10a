"""The Examples sections of the docstrings run, as doctests, against the installed package.

Every module of the package is searched (the docstrings a user reads with ``help``), so an example
that drifts from the code fails here. Numbers in examples are printed rounded, so that the last
digits of a minimiser or of a platform's libm cannot break them.
"""
from __future__ import annotations

import doctest
import importlib
import inspect
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
    "pyfrustrate.relaxation.relaxed_drawing", "pyfrustrate.montecarlo.anneal", "pyfrustrate.montecarlo.replica_exchange",
    "pyfrustrate.montecarlo.geometric_temperatures", "pyfrustrate.montecarlo.binding",
    "pyfrustrate.montecarlo.MonteCarloOptions", "pyfrustrate.montecarlo.clusters",
    "pyfrustrate.montecarlo.classify_aggregate", "pyfrustrate.montecarlo.draw_snapshot",
    "pyfrustrate.plotting.figure", "pyfrustrate.plotting.draw_hexagons", "pyfrustrate.plotting.check_figure",
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


#: Modules whose every public function and class documents its parameters in numpydoc sections.
DOCUMENTED_MODULES = ["pyfrustrate._checks", "pyfrustrate.ansatz", "pyfrustrate.boundary_layer", "pyfrustrate.chain",
                      "pyfrustrate.continuum", "pyfrustrate.ground_states", "pyfrustrate.io", "pyfrustrate.particles",
                      "pyfrustrate.montecarlo.analysis", "pyfrustrate.montecarlo.annealing",
                      "pyfrustrate.montecarlo.checkpoints", "pyfrustrate.montecarlo.drawing",
                      "pyfrustrate.montecarlo.driver", "pyfrustrate.montecarlo.exchange",
                      "pyfrustrate.montecarlo.options", "pyfrustrate.montecarlo.trajectory", "pyfrustrate.plotting",
                      "pyfrustrate.provenance", "pyfrustrate.random_particles", "pyfrustrate.relaxation",
                      "pyfrustrate.topology"]


def public_callables(module):
    """(qualified name, function) of the module's public functions, classes (their constructor)
    and methods, defined in the module itself."""
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj):
            yield f"{module.__name__}.{name}", obj, obj
        elif inspect.isclass(obj):
            yield f"{module.__name__}.{name}", obj, obj
            for method_name, method in vars(obj).items():
                function = method.__func__ if isinstance(method, (classmethod, staticmethod)) else method
                if not method_name.startswith("_") and inspect.isfunction(function):
                    yield f"{module.__name__}.{name}.{method_name}", function, function


def documented_names(doc: str) -> set[str]:
    """Names listed in the Parameters, Attributes and Other Parameters sections of a numpydoc
    docstring (``a, b : type`` lines count for both)."""
    names, section = set(), None
    lines = doc.splitlines()
    for line, underline in zip(lines, lines[1:] + [""]):
        if underline.strip() and set(underline.strip()) == {"-"}:
            section = line.strip()
            continue
        if set(line.strip()) == {"-"}:
            continue
        if section in ("Parameters", "Attributes", "Other Parameters") and line and not line[0].isspace():
            head = line.split(" : ")[0].strip()
            names |= {n.strip().lstrip("*") for n in head.split(",")}
    return names


def documented_parameters_cases():
    for module_name in DOCUMENTED_MODULES:
        module = importlib.import_module(module_name)
        yield from (pytest.param(q, obj, target, id=q) for q, obj, target in public_callables(module))


@pytest.mark.parametrize("name, obj, target", list(documented_parameters_cases()))
def test_every_parameter_is_documented(name, obj, target):
    """Each parameter of a public function, method or class constructor appears in its
    docstring's Parameters (or, for result classes, Attributes) section, and nothing listed
    there is missing from the signature: a renamed parameter fails here."""
    doc = inspect.getdoc(obj) or ""
    assert doc, f"{name} has no docstring"
    try:
        signature = inspect.signature(target)
    except (TypeError, ValueError):
        return
    parameters = {p.name for p in signature.parameters.values() if p.name not in ("self", "cls")}
    if inspect.isclass(obj) and obj.__init__ is object.__init__:
        parameters = set()
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        return
    listed = documented_names(doc)
    if inspect.isclass(obj) and getattr(obj, "_is_protocol", False):
        return  # a Protocol documents the attributes it asks for, not a constructor
    assert parameters <= listed, f"{name}: {sorted(parameters - listed)} not documented"
    if not inspect.isclass(obj):
        assert listed <= parameters, f"{name}: documents {sorted(listed - parameters)}, which it does not take"
