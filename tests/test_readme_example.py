"""The README's first example runs as printed, and says what the continuum says: the catalogue's
optimal fibre width at the paper's point is within a lattice line of the continuum's W*."""
from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_the_readme_example_runs_and_agrees_with_the_continuum():
    section = README.read_text().split("## A first example", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.DOTALL).group(1)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, str(README), "exec"), {})
    output = printed.getvalue()
    catalogue = float(re.search(r"W\* = ([0-9.]+) lattice spacings", output).group(1))
    theory = float(re.search(r"continuum: W\* = ([0-9.]+)", output).group(1))
    # One lattice line is sqrt(3)/2 of a lattice spacing: the catalogue's widths step by it.
    assert abs(catalogue - theory) < 3 ** 0.5 / 2, output
    assert "converged True" in output, output
