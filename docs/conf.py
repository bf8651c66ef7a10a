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


# Today's docstrings are plain text in places where reST reads markup. Until they are written as
# numpydoc throughout (then remove this), three patterns are rewritten when autodoc reads them,
# so that -W stays strict for everything else:
# - ``*shape(g)`` (unpacking) and ``|z|`` (a modulus) outside inline literals: escaped;
# - ``name``s (a literal with a suffix): the suffix separated by an escaped space;
# - aligned "term   description" tables (a term that is a literal or one word, two or more
#   spaces, its description, continuation lines indented): made a definition list.
_LITERAL = re.compile(r"(``.+?``)")
_UNPACKING = re.compile(r"(?<=[(\[, ])\*(?=\w[^*]*$)")  # a '*' that no other '*' closes
_MODULUS = re.compile(r"(?<!\\)\|(\w+)\|")
_TABLE_ITEM = re.compile(r"^((?:``[^`]+``(?:, ``[^`]+``)*)|[A-Za-z_]\w*)\s{2,}(\S.*)$")


def _escape_outside_literals(line: str) -> str:
    parts = _LITERAL.split(line)  # literals at the odd indices, paired left to right
    for k in range(0, len(parts), 2):
        parts[k] = _MODULUS.sub(r"\\|\1\\|", _UNPACKING.sub(r"\\*", parts[k]))
        if k > 0 and parts[k][:1].isalpha():
            parts[k] = "\\ " + parts[k]
    return "".join(parts)


def _aligned_tables_to_definition_lists(lines: list[str]) -> list[str]:
    out: list[str] = []
    i = 0
    while i < len(lines):
        items = []
        j = i
        while j < len(lines) and (item := _TABLE_ITEM.match(lines[j])):
            term, text = item.group(1), [item.group(2)]
            j += 1
            while j < len(lines) and lines[j].startswith("    ") and lines[j].strip():
                text.append(lines[j].strip())
                j += 1
            items.append((term, " ".join(text)))
        if len(items) >= 2:
            if out and out[-1].strip():
                out.append("")
            for term, text in items:
                out += [term, "    " + text, ""]
            i = j
        else:
            out.append(lines[i])
            i += 1
    return out


def _escape_plain_text(app, what, name, obj, options, lines):
    lines[:] = _aligned_tables_to_definition_lists([_escape_outside_literals(line) for line in lines])


def setup(app):
    app.connect("autodoc-process-docstring", _escape_plain_text)


# Sphinx 9.0's autosummary cuts a summary at the first ". " even inside an inline literal
# (``start .. start + n``): its check for broken markup re-parses the whole stanza instead of the
# cut. Where the cut leaves a literal open, the summary is the whole first paragraph instead.
import sphinx.ext.autosummary as _autosummary  # noqa: E402

_extract_summary = _autosummary.extract_summary


def _summary_with_closed_literals(doc, settings):
    summary = _extract_summary(doc, settings)
    if summary.count("``") % 2 == 0:
        return summary
    paragraph = []
    for line in doc:
        if not line.strip():
            if paragraph:
                break
            continue
        paragraph.append(line.strip())
    return " ".join(paragraph)


_autosummary.extract_summary = _summary_with_closed_literals
