"""The package's surface cannot be misread (issue 34, item 7).

* ``import pyfrustrate as pf`` reaches every public submodule as an attribute, and no function
  hides a submodule by bearing its name;
* the same mistake raises the same exception everywhere: a non-particle where a particle goes is
  a ``TypeError`` naming the parameter;
* a request too large for memory is refused up front with a ``ValueError`` quoting the memory it
  would need, without allocating it.
"""
from __future__ import annotations

import importlib
import inspect
import os
import pkgutil
import re
import subprocess
import sys
import textwrap
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import pyfrustrate as pf
from pyfrustrate import _checks, ansatz, boundary_layer, chain, ground_states, random_particles, relaxation, topology

PACKAGE = Path(pf.__file__).parent


def public_submodules() -> list[str]:
    """Dotted names of every public module of the installed package, found on disk (not through
    the package's own imports, which are what is under test)."""
    names = []
    for info in pkgutil.walk_packages(pf.__path__, prefix="pyfrustrate."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def test_submodules_are_found():
    found = public_submodules()
    for name in ("pyfrustrate.ansatz", "pyfrustrate.ground_states", "pyfrustrate.plotting", "pyfrustrate.relaxation",
                 "pyfrustrate.io", "pyfrustrate.boundary_layer", "pyfrustrate.topology", "pyfrustrate.continuum"):
        assert name in found


@pytest.mark.parametrize("name", public_submodules())
def test_every_submodule_is_an_attribute_of_the_package(name):
    # In a fresh interpreter: this process's other tests may have imported the submodule already,
    # which binds it on its package whatever pyfrustrate/__init__.py does.
    parent, _, short = name.rpartition(".")
    code = (f"import sys, importlib; import {parent} as p; obj = getattr(p, {short!r}); "
            f"assert obj is importlib.import_module({name!r}), repr(obj)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/")
    assert done.returncode == 0, done.stderr[-2000:]


@pytest.mark.parametrize("name", public_submodules())
def test_no_attribute_hides_a_submodule(name):
    parent, _, short = name.rpartition(".")
    module = importlib.import_module(name)
    attribute = getattr(importlib.import_module(parent), short)
    assert inspect.ismodule(attribute), f"{parent}.{short} is {attribute!r}, which hides the module {name}"
    assert attribute is module


def test_plotting_is_loaded_lazily():
    """matplotlib is imported on first use of ``pf.plotting``, not by ``import pyfrustrate``."""
    code = ("import sys, pyfrustrate as pf; assert 'matplotlib' not in sys.modules; "
            "pf.plotting.draw_hexagons; assert 'matplotlib' in sys.modules; "
            "assert 'plotting' in dir(pf)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/")
    assert done.returncode == 0, done.stderr[-2000:]


def test_unknown_attribute_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'plotter'"):
        pf.plotter  # noqa: B018


def test_all_names_exist():
    for name in pf.__all__:
        assert getattr(pf, name) is not None


# --------------------------------------------------------------------------------------------
# A non-particle where a particle goes: TypeError naming the parameter, everywhere.
# --------------------------------------------------------------------------------------------

NOT_PARTICLES = {"a topology": topology.disk(1), "None": None, "a number": 2.0, "a class": pf.Hexagon}


def particle_entry_points():
    """(name, call taking the would-be particle): every public function that takes a particle."""
    disk = topology.disk(1)
    state = disk.reference_state()
    cases = [
        ("relax", lambda p: pf.relax(p, disk)),
        ("relaxation.energy", lambda p: relaxation.energy(p, disk, state)),
        ("relaxation.particle_energies", lambda p: relaxation.particle_energies(p, disk, state)),
        ("relaxation.particle_corners", lambda p: relaxation.particle_corners(p, disk, state)),
        ("relaxation.relaxed_drawing", lambda p: relaxation.relaxed_drawing(p, disk)),
        ("ansatz.relax_catalogue", lambda p: ansatz.relax_catalogue(p, ansatz.catalogue(1, 2))),
        ("ansatz.binding_energy_of", lambda p: ansatz.binding_energy_of(p, 5.0, 0.5, 0.5)),
        ("ansatz.finite_aggregates", lambda p: ansatz.finite_aggregates(p, 7)),
        ("ground_states.box_candidates", lambda p: ground_states.box_candidates(p, 7, 8)),
        ("random_particles.binding_energy_of", lambda p: random_particles.binding_energy_of(p, 2.0, 0.5, 0.5)),
        ("random_particles.edge_energy_profile", lambda p: random_particles.edge_energy_profile(p, 8)),
        ("random_particles.fitted_boundary_layer_length",
         lambda p: random_particles.fitted_boundary_layer_length(p)),
        ("random_particles.aggregation_line", lambda p: random_particles.aggregation_line(p, [0.5], 2.0, 0.5)),
    ]
    params = [pytest.param(call, id=name) for name, call in cases]
    # The Monte Carlo entry points (pyfrustrate/montecarlo) call _checks.particle too.
    params.append(pytest.param(lambda p: pf.anneal(p, g=0.1, box=6, n=4, seed=1, progress=False), id="anneal"))
    params.append(pytest.param(lambda p: pf.replica_exchange(p, g=0.1, temperatures=[0.5, 1.0], box=6, n=4, rounds=1,
                                                                  seed=1, progress=False),
                               id="replica_exchange"))
    return params


@pytest.mark.parametrize("call", particle_entry_points())
@pytest.mark.parametrize("wrong", list(NOT_PARTICLES), ids=list(NOT_PARTICLES))
def test_a_non_particle_is_a_type_error_naming_the_parameter(call, wrong):
    with pytest.raises(TypeError, match=r"^particle must be a particle model"):
        call(NOT_PARTICLES[wrong])


def test_the_check_passes_every_particle_model_through():
    for p in (pf.Hexagon.from_continuum(2.0, 0.5), pf.Triangle.from_continuum(2.0, 0.5),
              pf.RandomHexagon.draw(seed=1)):
        assert _checks.particle("particle", p) is p
        assert isinstance(p, pf.Particle)


# --------------------------------------------------------------------------------------------
# Requests too large for memory: refused up front, with the figure, without allocating.
# --------------------------------------------------------------------------------------------

FIGURE = re.compile(r"would need about ([\d.]+) (B|KiB|MiB|GiB|TiB|PiB|EiB|ZiB|YiB) of memory")
UNITS = {"B": 0, "KiB": 1, "MiB": 2, "GiB": 3, "TiB": 4, "PiB": 5, "EiB": 6, "ZiB": 7, "YiB": 8}


def quoted_bytes(message: str) -> float:
    match = FIGURE.search(message)
    assert match, f"no memory figure in {message!r}"
    return float(match.group(1)) * 1024.0 ** UNITS[match.group(2)]


HEXAGON = pf.Hexagon.from_continuum(2.0, 0.5)
#: (request, call, a lower bound on the bytes it needs, from the arrays the request implies alone)
HUGE = [
    ("topology.disk", lambda: topology.disk(10**7), 8 * (2 * 10**7 + 1) ** 2),  # one int64 grid
    ("topology.disk triangle", lambda: topology.disk(10**7, tiling="triangle"), 8 * (2 * 10**7 + 2) ** 2),
    ("topology.hexagon_sites", lambda: topology.hexagon_sites(10**7), 8 * (2 * 10**7 + 1) ** 2),
    ("topology.triangle_hexagon_sites", lambda: topology.triangle_hexagon_sites(10**7), 8 * (2 * 10**7 + 2) ** 2),
    ("topology.fiber", lambda: topology.fiber(10**13), 8 * 2 * 10**13),  # the cell's (i, j) sites
    ("topology.fiber triangle", lambda: topology.fiber(10**7, cut=2, tiling="triangle"), 8 * (4 * 10**7) ** 2),
    ("topology.stadium_sites n", lambda: topology.stadium_sites(10**15), 8 * 4 * 10**15),
    ("topology.stadium_sites segment", lambda: topology.stadium_sites(7, segment=1e9), 8 * (2 * 1e9) ** 2),
    ("ansatz.catalogue", lambda: ansatz.catalogue(max_radius=10**5, max_width=10), 16 * (10**5) ** 3),
    ("chain.relax", lambda: chain.relax(10**15), 2 * 8 * 10**15),
    ("chain.analytic_shift", lambda: chain.analytic_shift(10**15, 1.0, 0.01, 0.01), 8 * 10**15),
    ("random_particles.elasticity_matrices", lambda: random_particles.elasticity_matrices(10**12, 1), 648 * 10**12),
    ("random_particles.sample_properties", lambda: random_particles.sample_properties(10**12, 1), 648 * 10**12),
    ("random_particles.line_tension_grid", lambda: random_particles.line_tension_grid(10.0, 10**15), 8 * 10**15),
    ("ground_states.box_candidates", lambda: ground_states.box_candidates(HEXAGON, 7, 10**8), 10**16),
    ("ansatz.finite_aggregates", lambda: ansatz.finite_aggregates(HEXAGON, 10**15), 8 * 4 * 10**15),
    ("random_particles.edge_energy_profile", lambda: random_particles.edge_energy_profile(HEXAGON, 10**13),
     8 * 2 * 10**13),
    ("boundary_layer.finite_depth_boundary_layer_length",
     lambda: boundary_layer.finite_depth_boundary_layer_length(random_particles.elasticity_matrices(1, 1)[0], 10**13),
     8 * 2 * 10**13),
]


@pytest.mark.parametrize("call, lower_bound", [pytest.param(c, b, id=i) for i, c, b in HUGE])
def test_a_request_too_large_for_memory_is_refused_with_its_figure(call, lower_bound):
    tracemalloc.start()
    try:
        with pytest.raises(ValueError) as refused:
            call()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 50 * 2**20, f"allocated {peak} bytes before refusing"  # numpy reports to tracemalloc
    needed = quoted_bytes(str(refused.value))
    assert needed >= lower_bound * (1 - 5e-3)  # three significant figures quoted
    assert "this machine has" in str(refused.value)


def test_the_threshold_is_a_share_of_this_machines_memory(monkeypatch):
    """With 1 GiB of memory, a disk whose grids alone take more than half of it is refused and a
    small one is built; the message quotes the (pretended) machine."""
    monkeypatch.setattr(_checks, "physical_memory", lambda: 2**30)
    R = 2000  # 1.2e7 particles
    with pytest.raises(ValueError, match=r"disk\(R=2000\) would need about .* this machine has 1 GiB"):
        topology.disk(R)
    assert topology.disk(3).n_particles == 1 + 3 * 3 * 4


def test_byte_count_units():
    assert _checks.byte_count(512) == "512 B"
    assert _checks.byte_count(2.84 * 2**50) == "2.84 PiB"
    assert _checks.byte_count(1536) == "1.5 KiB"


def test_physical_memory_is_this_machines():
    memory = _checks.physical_memory()
    if memory is None:
        pytest.skip("os.sysconf does not report physical memory here")
    meminfo = Path("/proc/meminfo")
    if meminfo.is_file():
        total_kib = int(re.search(r"MemTotal:\s+(\d+) kB", meminfo.read_text()).group(1))
        assert abs(memory - total_kib * 1024) <= 0.01 * memory


def traced_peak(build):
    """``build()`` and the peak of the memory Python and numpy allocated meanwhile (tracemalloc)."""
    tracemalloc.start()
    try:
        out = build()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return out, peak


@pytest.mark.parametrize("builder, build, cells", [
    pytest.param("hexagon_sites", lambda: topology.hexagon_sites(300), (2 * 300 + 1) ** 2, id="hexagon_sites"),
    pytest.param("triangle_hexagon_sites", lambda: topology.triangle_hexagon_sites(300), (2 * 300 + 2) ** 2,
                 id="triangle_hexagon_sites"),
    pytest.param("stadium_sites", lambda: topology.stadium_sites(10000, faceted=True), (4 * (100 + 2) + 1) ** 2,
                 id="stadium_sites faceted"),
    pytest.param("stadium_sites", lambda: topology.stadium_sites(100, segment=300.0), (4 * (150 + 10 + 2) + 1) ** 2,
                 id="stadium_sites segment"),
    pytest.param("triangle_fiber", lambda: topology._triangle_fiber_sites(150, 2), (4 * 150 + 9) ** 2,
                 id="triangle_fiber_cell"),
])
def test_the_grid_estimate_bounds_the_site_builders(builder, build, cells):
    """The numpy grids a site builder scans take at most GRID_BYTES_PER_CELL[builder] per cell."""
    _, peak = traced_peak(build)
    assert peak <= cells * topology.GRID_BYTES_PER_CELL[builder]
    assert peak >= cells * 16  # and the bound is not vacuous: at least two int64 per cell


def test_the_fibre_estimate_bounds_its_connectivity_check():
    width = 2000
    fibre, peak = traced_peak(lambda: topology.fiber(width))
    assert fibre.n_particles == width
    assert peak <= 2 * width * topology.FIBER_BYTES_PER_PARTICLE
    assert peak >= width * 9 * 56  # not vacuous: nine images of every site, a tuple each


@pytest.mark.skipif(not Path("/proc/self/statm").is_file(), reason="needs Linux's /proc to read resident memory")
def test_the_topology_estimate_bounds_the_kernels_corner_graph():
    """The kernel's memory is invisible to tracemalloc: in a fresh process (whose allocator has no
    freed pages to reuse, and no heap top pad), resident memory grows by at most
    TOPOLOGY_BYTES_PER_PARTICLE per particle when the kernel builds a disk of 68 000 particles
    (tens of megabytes)."""
    code = textwrap.dedent("""
        import os
        from pathlib import Path
        from pyfrustrate import topology
        def resident():
            return int(Path("/proc/self/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE")
        sites = topology.hexagon_sites(150)
        before = resident()
        t = topology.cluster(sites)
        print(t.n_particles, resident() - before)
    """)
    # Without the kernel's heap top pad (kernel/module.cpp), 16 MiB the heap keeps at its top
    # whatever the topology (measured with it: 27.8 MB grown against a bound of 27.2).
    env = dict(os.environ, PYFRUSTRATE_MALLOC_TOP_PAD="0")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/", check=True, env=env)
    n_particles, grown = (int(v) for v in done.stdout.split())
    assert n_particles == 1 + 3 * 150 * 151
    assert grown <= n_particles * topology.TOPOLOGY_BYTES_PER_PARTICLE
    assert grown >= n_particles * 2 * 8  # it did build something of that order (corners, two floats each)
