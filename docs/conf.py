"""Sphinx configuration of the pyfrustrate documentation (built by scripts/docs.sh into
results/docs/, with warnings as errors). Laid out after freud's doc/source: getting started,
tutorials, topics, gallery, API reference, development guide, changelog."""
from __future__ import annotations

import pkgutil
import re
import sys
from pathlib import Path

import pyfrustrate

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

project = "pyfrustrate"
author = "pyfrustrate developers"
copyright = "2026, pyfrustrate developers"
release = version = pyfrustrate.__version__

# One version: the package's. CITATION.cff repeats it for citation tools, so it is checked here.
_cff_version = re.search(r"^version:\s*(\S+)", (ROOT / "CITATION.cff").read_text(), re.MULTILINE)
if not _cff_version or _cff_version.group(1) != release:
    raise RuntimeError(f"CITATION.cff's version ({_cff_version and _cff_version.group(1)}) differs from "
                       f"pyfrustrate.__version__ ({release}): update CITATION.cff")

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_design",
    "sphinx_gallery.gen_gallery",
    "measured",
    "figure_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "tutorials_src", "**/GALLERY_HEADER.rst", "README.md"]
templates_path = ["_templates"]

# Markdown pages: fenced directives, definition lists. Formulas are plain text (as in the
# docstrings), so that pages read offline: MathJax would come from a CDN.
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 3

# API reference: one page per public module, class and function (templates in _templates/).
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types
# numpydoc: member tables come from the class template, not numpydoc's autosummary stubs
# (which would name every inherited attribute as a missing document).
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# Executed tutorials: every docs/tutorials_src/tutorial_*.py runs at each build; an error fails it.
sphinx_gallery_conf = {
    "examples_dirs": ["tutorials_src"],
    "gallery_dirs": ["tutorials"],
    "filename_pattern": r"tutorial_",
    "abort_on_example_error": True,
    "write_computation_times": False,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
}

# The API reference lists every public module of the package, found at build time (so that a new
# module appears without editing the page): docs/api.rst is written from api.rst.in.
_PUBLIC_MODULES = sorted(m.name for m in pkgutil.iter_modules(pyfrustrate.__path__) if not m.name.startswith("_"))
_api_page = (Path(__file__).parent / "api.rst.in").read_text().replace(
    "@MODULES@", "\n".join(f"   pyfrustrate.{name}" for name in _PUBLIC_MODULES))
if not (Path(__file__).parent / "api.rst").is_file() or (Path(__file__).parent / "api.rst").read_text() != _api_page:
    (Path(__file__).parent / "api.rst").write_text(_api_page)

# Measured numbers (docs/_ext/measured.py): every file a page may quote, with what (re)writes it.
measured_sources = {
    "results/benchmarks/relax.csv": "python benchmarks/bench_relax.py --csv results/benchmarks/relax.csv",
    "results/benchmarks/speed_accuracy.csv": "bash scripts/figures.sh results/benchmarks/speed_accuracy.csv (rule speed_accuracy: benchmarks/bench_tradeoff.py)",
    "results/ansatz/line_tension.json": "bash scripts/figures.sh results/ansatz/line_tension.json (rule ansatz_line_tension)",
    "results/montecarlo/validation.json": "bash scripts/figures.sh results/montecarlo/validation.json (rule montecarlo_validation)",
    "benchmarks/results/anneal_defaults.csv": "python benchmarks/bench_anneal_defaults.py",
    "benchmarks/results/large_control.csv": "python benchmarks/bench_large_control.py --jobs 2",
    "benchmarks/results/large_nucleation.csv": "CANDIDATES=RESULTS/montecarlo/finite/n{n}_nu{nu:g}.npz bash benchmarks/large_nucleation.sh",
    "benchmarks/results/large_merging.csv": "CANDIDATES=RESULTS/montecarlo/finite/n{n}_nu{nu:g}.npz bash benchmarks/large_nucleation.sh",
    "benchmarks/results/parent_relax.csv":
        "python benchmarks/bench_parent_relax.py --repeats 7 --baseline BASE --csv benchmarks/results/parent_relax.csv",
    "benchmarks/results/mc_goals_speed_dense.csv":
        "python benchmarks/bench_mc_goals.py --only 'b dense' --dense-sweeps 1000 --starts warm --baseline BASE "
        "--csv benchmarks/results/mc_goals_speed_dense.csv",
    "benchmarks/results/mc_goals_speed_sparse.csv":
        "python benchmarks/bench_mc_goals.py --only 'c sparse nu=0.4 Gamma=0.1' 'c sparse nu=0.9 Gamma=0.5' "
        "--sparse-sweeps 2000 --starts warm --baseline BASE --csv benchmarks/results/mc_goals_speed_sparse.csv",
    "benchmarks/results/large_runs.csv":
        "python benchmarks/bench_large_runs.py --compare --sweeps 400 --descent-rounds 2 --repeats 2 "
        "--variants workflow parent64 --csv benchmarks/results/large_runs.csv",
    "benchmarks/results/validation_samples.csv":
        "python benchmarks/bench_validation_samples.py --cases fibre:15 fibre:25:0.8 disk:660 disk:1634:0.8 "
        "--sweeps 4 --repeats 2 --csv benchmarks/results/validation_samples.csv",
    "benchmarks/results/finite_holes.csv":
        "python benchmarks/bench_finite_holes.py --repeats 2 --csv benchmarks/results/finite_holes.csv",
    "benchmarks/results/allocator.csv":
        "python benchmarks/bench_allocator.py --cases disk:660 fibre:15 fibre:25:0.8 --repeats 3 "
        "--csv benchmarks/results/allocator.csv",
    "benchmarks/results/large_runs_quick.csv":
        "python benchmarks/bench_large_runs.py --compare --n 400 --box 85 --sweeps 4000 --repeats 1 "
        "--variants workflow parent64 --csv benchmarks/results/large_runs_quick.csv",
    "benchmarks/results/large_runs_screened_quick.csv":
        "python benchmarks/bench_large_runs.py --compare --n 400 --box 85 --sweeps 4000 --repeats 1 "
        "--variants parent64 parent64+screened --csv benchmarks/results/large_runs_screened_quick.csv",
    "benchmarks/results/large_profile_parent64_screened.csv":
        "python benchmarks/bench_large_runs.py --profile --sweeps 1500 --variants parent64+screened "
        "--out benchmarks/results/large_profile_parent64_screened.txt --csv benchmarks/results/large_profile_parent64_screened.csv",
    "benchmarks/results/mc_rules_quick_before.csv":
        "bash scripts/mc_rule_benchmarks.sh 4e30625 quick benchmarks/results/mc_rules_quick_before.csv",
    "benchmarks/results/mc_rules_quick_after.csv":
        "bash scripts/mc_rule_benchmarks.sh HEAD quick benchmarks/results/mc_rules_quick_after.csv",
    "benchmarks/results/mc_rules_paper_pairs.csv":
        "MC_PAIR_WORK=DIR bash scripts/mc_rule_pairs.sh 4e30625 HEAD paper benchmarks/results/mc_rules_paper_pairs.csv "
        "$(cat DIR/targets.txt)",
}

html_theme = "pydata_sphinx_theme"
html_title = f"pyfrustrate {release}"
html_static_path = ["_static"]
html_css_files = ["pyfrustrate.css"]
html_show_sourcelink = False
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
# Pages without sub-pages get no (empty) section navigation on the left.
html_sidebars = {page: [] for page in ("index", "gallery", "changelog", "results_log", "api")}

# Docstrings are read as written (numpydoc sections, reST definition lists), with no rewriting, so
# -W stays strict for every one. Sphinx 9's autosummary cuts a summary at the first ". " even inside
# an inline literal: a first sentence keeps ". " out of its literals.
