"""The type stub of the compiled kernel (``pyfrustrate/_kernel.pyi``, written at build time by
pybind11-stubgen, CMakeLists.txt) and the ``py.typed`` marker, as an installed package has them.

The stub is checked against the module it describes (every public name and every public
member of every class), and a type checker is run over code that uses the package the way a
user's would: the signatures must be usable, not merely present.
"""
from __future__ import annotations

import ast
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from pyfrustrate import _kernel

PACKAGE = Path(_kernel.__file__).parent
REPOSITORY = Path(__file__).resolve().parent.parent
STUB = PACKAGE / "_kernel.pyi"


def public(names):
    return {n for n in names if not n.startswith("_")}


@pytest.fixture(scope="module")
def stub_tree() -> ast.Module:
    assert STUB.is_file(), f"no type stub next to the installed kernel ({PACKAGE})"
    return ast.parse(STUB.read_text(), filename=str(STUB))


def defined_names(body) -> dict[str, ast.AST]:
    """Names a stub body defines: classes, functions (each overload), annotated or plain assignments."""
    out: dict[str, ast.AST] = {}
    for node in body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[node.target.id] = node
        elif isinstance(node, ast.Assign):
            out.update({t.id: node for t in node.targets if isinstance(t, ast.Name)})
    return out


def test_stub_and_marker_are_installed():
    assert (PACKAGE / "py.typed").is_file(), "py.typed missing: type checkers would ignore the package's types"
    assert STUB.is_file()
    # Generated from this very build: older than the module it describes would mean a stale copy.
    assert STUB.stat().st_mtime >= Path(_kernel.__file__).stat().st_mtime - 1


def test_stub_names_every_public_attribute_of_the_module(stub_tree):
    stubbed = defined_names(stub_tree.body)
    missing = public(dir(_kernel)) - set(stubbed)
    assert not missing, f"the stub lacks {sorted(missing)}"
    extra = public(stubbed) - public(dir(_kernel))
    assert not extra, f"the stub names what the module lacks: {sorted(extra)}"


def test_stub_classes_name_every_public_member(stub_tree):
    classes = {n: node for n, node in defined_names(stub_tree.body).items() if isinstance(node, ast.ClassDef)}
    assert classes, "no class in the stub"
    for name, node in classes.items():
        members = public(dir(getattr(_kernel, name)))
        missing = members - set(defined_names(node.body))
        assert not missing, f"{name}: the stub lacks {sorted(missing)}"


def test_stub_has_no_placeholder_types(stub_tree):
    # pybind11-stubgen writes `...` for an annotation it cannot express (and the build's
    # --exit-code refuses that): none may be left, nor C++ type names leaking through.
    annotations = []
    for node in ast.walk(stub_tree):
        if isinstance(node, ast.arg) and node.annotation is not None:
            annotations.append((node.arg, node.annotation))
        elif isinstance(node, ast.FunctionDef) and node.returns is not None:
            annotations.append((f"{node.name} (return)", node.returns))
    assert len(annotations) > 100
    for where, annotation in annotations:
        text = ast.unparse(annotation)
        assert text != "...", f"untyped {where} in the stub"
        assert "::" not in text, f"C++ type name in the annotation of {where}: {text}"


def run_mypy(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    # A run from an empty directory: the installed package (with its stub), not the source
    # tree, is what mypy must find, as in a user's project.
    env = {k: v for k, v in os.environ.items() if k not in ("MYPYPATH", "PYTHONPATH")}
    return subprocess.run([sys.executable, "-m", "mypy", "--no-error-summary", "--cache-dir", str(tmp_path / "cache"),
                           "--python-executable", sys.executable, *args],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)


def test_mypy_accepts_user_code_and_the_package(tmp_path):
    pytest.importorskip("mypy")
    user = tmp_path / "user.py"
    user.write_text(textwrap.dedent("""
        import numpy as np
        import pyfrustrate as pf
        from pyfrustrate import _kernel, continuum, topology

        particle = pf.Hexagon.from_continuum(ell=2.0, nu=0.3, eps=0.01)
        disk = topology.disk(2)
        result = pf.relax(particle, disk, method="linear")
        e: float = result.energy
        cache = _kernel.StiffnessCache(disk.kernel)
        out = _kernel.relax_linear(particle._kernel_model, disk.kernel, cache)
        out = _kernel.relax_linear(particle._kernel_model, disk.kernel)
        n: int = disk.kernel.n_particles
        sites = disk.kernel.sites
        model = _kernel.HexagonModel(1.0, 0.01, 0.0, 0.01)
        energy, gradient, hessian = model.energy_of_displacement(np.zeros(12))
        k: float = model.k
        w = continuum.optimal_width(0.3, 0.5)
    """))
    user_run = run_mypy(tmp_path, str(user))
    assert user_run.returncode == 0, user_run.stdout + user_run.stderr
    # A mistake the stub must catch: a string where the kernel takes a number.
    wrong = tmp_path / "wrong.py"
    wrong.write_text("from pyfrustrate import _kernel\n_kernel.HexagonModel('stiff', 0.01, 0.0, 0.01)\n")
    wrong_run = run_mypy(tmp_path, str(wrong))
    assert wrong_run.returncode == 1 and "HexagonModel" in wrong_run.stdout, wrong_run.stdout + wrong_run.stderr
    # The package itself, with the repository's settings (pyproject.toml: scipy and tqdm have no
    # types): every use of the kernel type-checks against the stub.
    package_run = run_mypy(tmp_path, "--config-file", str(REPOSITORY / "pyproject.toml"), "-p", "pyfrustrate")
    assert package_run.returncode == 0, package_run.stdout + package_run.stderr
