"""Measured numbers in the documentation, read from the files that benchmarks and workflow rules
write, never typed by hand.

The role ``{measured}`PATH:SELECTOR%FORMAT``` (MyST) or ``:measured:`PATH:SELECTOR%FORMAT```
(reST) inserts one value:

* ``PATH`` is relative to the repository's root, e.g. ``results/benchmarks/relax.csv``. It must
  be registered in ``measured_sources`` (conf.py) with the command that (re)writes it.
* ``SELECTOR`` walks the file's content: ``.key`` (or ``."key with spaces"``) takes a key of a
  JSON object or a column of a CSV row; ``[k=v,k=v]`` takes the one record of a list (a CSV file
  is the list of its rows) whose fields equal those values. Exactly one record must match.
* ``FORMAT`` (optional) is a Python format spec, e.g. ``.1f`` or ``.2g`` (after ``%``, not
  ``|``, which would end a Markdown table's cell).

The value comes from ``PATH`` itself when a benchmark or the workflow has written it in this
checkout, or else from the committed snapshot ``docs/_generated/PATH`` (what a fresh clone
builds with); the page says which through a tooltip and the directive ``measured-sources``
lists every source, its origin and its provenance. When neither exists the role renders
"not measured" with the command that measures it: a missing number is never replaced by a
typed one. A selector that does not match is an error (the build runs with ``-W``).
"""
from __future__ import annotations

from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive

from measured_values import formatted, load, select

SNAPSHOT_DIR = "docs/_generated"


def _repository_root(app) -> Path:
    return Path(app.confdir).resolve().parent


def locate(app, path: str) -> tuple[Path | None, str]:
    """The file a role reads, and where it came from ('this checkout' or 'snapshot')."""
    root = _repository_root(app)
    if (root / path).is_file():
        return root / path, "this checkout"
    if (root / SNAPSHOT_DIR / path).is_file():
        return root / SNAPSHOT_DIR / path, "snapshot"
    return None, "missing"


def measured_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    app = inliner.document.settings.env.app
    reference, _, spec = text.partition("%")
    path, _, selector = reference.partition(":")
    path, selector = path.strip(), selector.strip()
    sources = app.config.measured_sources
    if path not in sources:
        message = inliner.reporter.error(f"measured: '{path}' is not registered in measured_sources (conf.py)",
                                         line=lineno)
        return [inliner.problematic(rawtext, rawtext, message)], [message]
    file, origin = locate(app, path)
    app.env.note_dependency(str(_repository_root(app) / path))
    app.env.note_dependency(str(_repository_root(app) / SNAPSHOT_DIR / path))
    if file is None:
        node = nodes.emphasis(text=f"not measured in this checkout (run: {sources[path]})")
        return [node], []
    try:
        value = select(load(file), selector)
        shown = formatted(value, spec.strip())
    except (KeyError, ValueError) as error:
        message = inliner.reporter.error(f"measured: {path}:{selector}: {error}", line=lineno)
        return [inliner.problematic(rawtext, rawtext, message)], [message]
    node = nodes.abbreviation(text=shown, explanation=f"{path} ({origin}), written by: {sources[path]}")
    node["classes"].append("measured")
    return [node], []


def provenance_summary(file: Path) -> str:
    """The commit and package version a result file records (pyfrustrate.io.read_provenance)."""
    try:
        from pyfrustrate.io import read_provenance

        record = read_provenance(file) or {}
    except Exception as error:  # a file without a readable record still gets listed
        return f"no readable provenance ({type(error).__name__})"
    if not record:
        return "no provenance recorded"
    parts = [f"version {record['version']}"] if "version" in record else []
    if "git_commit" in record:
        parts.append(f"commit {str(record['git_commit'])[:10]}")
    if record.get("rule"):
        parts.append(f"rule {record['rule']}")
    if record.get("git_dirty"):
        parts.append("uncommitted changes")
    return ", ".join(parts) or "recorded"


class MeasuredSources(Directive):
    """A table of every registered source: path, the command that writes it, where this build
    read it from, and its provenance."""

    def run(self):
        app = self.state.document.settings.env.app
        table = nodes.table()
        group = nodes.tgroup(cols=4)
        table += group
        for _ in range(4):
            group += nodes.colspec(colwidth=1)
        head, body = nodes.thead(), nodes.tbody()
        group += head
        group += body

        def row(cells, literal_first=True):
            tr = nodes.row()
            for i, cell in enumerate(cells):
                entry = nodes.entry()
                entry += nodes.paragraph("", "", nodes.literal(text=cell) if (i < 2 and literal_first) else nodes.Text(cell))
                tr += entry
            return tr

        head += row(["file", "written by", "read from", "provenance"], literal_first=False)
        root = _repository_root(app)
        for path, command in sorted(app.config.measured_sources.items()):
            file, origin = locate(app, path)
            # Re-read this page when a source appears, changes or goes (a missing dependency
            # keeps the page out of date, so a later measurement is picked up).
            app.env.note_dependency(str(root / path))
            app.env.note_dependency(str(root / SNAPSHOT_DIR / path))
            read_from = {"this checkout": path, "snapshot": f"{SNAPSHOT_DIR}/{path}", "missing": "nowhere: not measured"}[origin]
            body += row([path, command, read_from, provenance_summary(file) if file else "-"])
        return [table]


def setup(app):
    app.add_config_value("measured_sources", {}, "env")
    app.add_role("measured", measured_role)
    app.add_directive("measured-sources", MeasuredSources)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
