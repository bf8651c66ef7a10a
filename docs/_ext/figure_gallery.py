"""The figure gallery, generated at build time from the workflow itself: one entry per figure
that a rule marks with ``figure_png(NAME)`` (workflow/rules/*.smk), with its caption from
workflow/report/NAME.rst (the same text the Snakemake report shows, its values filled in from
the configuration of the profile that made the figure), the rule and the script that draw it,
and the PNG from results/figures/ when this checkout has built it, with the profile, commit and
version its provenance records. A figure not
built yet says which command makes it; that is not a warning, since a fresh clone has none.

The page, docs/gallery.rst, is written when the build starts (and is not committed).
"""
from __future__ import annotations

import re
from pathlib import Path


RULE = re.compile(r"^rule (\w+):\n((?:[ \t]+.*\n|\n)*)", re.MULTILINE)
FIGURE = re.compile(r'figure_png\("(\w+)"\)')
SCRIPT = re.compile(r'script:\s*\n\s*"([^"]+)"')
LEAD = re.compile(r"^\*\*([^*]+?)\.?\*\*")  # a caption's bold lead: "Paper Fig. 3b" or "Beyond the paper ..."


def figure_rules(root: Path) -> dict[str, tuple[str, str]]:
    """Figure name -> (rule, script path relative to the repository) for every figure rule."""
    found = {}
    for smk in sorted((root / "workflow" / "rules").glob("*.smk")):
        for match in RULE.finditer(smk.read_text() + "\n"):
            body = match.group(2)
            figure, script = FIGURE.search(body), SCRIPT.search(body)
            if figure:
                script_path = (smk.parent / script.group(1)).resolve().relative_to(root) if script else None
                found[figure.group(1)] = (match.group(1), str(script_path) if script_path else "(shell command)")
    return found


def section_of(name: str) -> str:
    return "Beyond the paper" if name.startswith("figX") else "Supplement" if name.startswith("figS") else "Main text"


def profile_of(png: Path) -> str:
    """Which profile (quick or paper), commit and version made a built figure, from the provenance
    in its PNG: the figure rules pass the configuration's ``profile`` as a param, and
    ``provenance.for_job`` records every param."""
    try:
        from pyfrustrate.io import read_provenance

        record = read_provenance(png) or {}
    except Exception:
        return "no readable provenance"
    profile = (record.get("parameters") or {}).get("profile")
    commit = str(record.get("git_commit", "unknown"))[:10]
    dirty = " (with uncommitted changes)" if record.get("git_dirty") else ""
    made = f"the **{profile}** profile" if profile else "an unrecorded profile"
    return f"{made}, commit {commit}{dirty}, version {record.get('version', '?')}"


def recorded_profile(png: Path) -> str | None:
    """The profile a built figure records in its provenance (None: not recorded)."""
    try:
        from pyfrustrate.io import read_provenance

        return ((read_provenance(png) or {}).get("parameters") or {}).get("profile")
    except Exception:
        return None


def profile_config(root: Path, profile: str | None) -> dict:
    """The workflow's configuration of ``profile``: config/config.yaml, with config/PROFILE.yaml
    over it when there is one (as ``--configfile`` does: nested sections merged key by key)."""
    import yaml

    def merged(base, over):
        return {**base, **{k: merged(base[k], v) if isinstance(v, dict) and isinstance(base.get(k), dict) else v
                           for k, v in over.items()}}

    config = yaml.safe_load((root / "config" / "config.yaml").read_text())
    override = root / "config" / f"{profile}.yaml"
    if profile and override.is_file():
        config = merged(config, yaml.safe_load(override.read_text()) or {})
    return config


def rendered_caption(caption: str, root: Path, profile: str | None) -> str:
    """A caption with its Jinja values filled in from the configuration of the profile that made
    the figure, as the Snakemake report fills them from its run's. The paragraph naming the profile
    ("Made by the ...") is left out: the gallery states it from the figure's provenance."""
    from types import SimpleNamespace

    import jinja2

    text = jinja2.Template(caption).render(snakemake=SimpleNamespace(config=profile_config(root, profile)))
    return "\n\n".join(par for par in text.strip().split("\n\n") if not par.startswith("Made by the "))


def rest_literal_text(text: str) -> str:
    """``text`` as plain reStructuredText on one line: inline-markup characters escaped (a rule's
    sentence may hold ``*``, ``_`` or ``|``, as in ``W*`` or ``n_mc``), line breaks joined, so that it
    can sit in a line block without starting emphasis, a reference or a substitution."""
    escaped = re.sub(r"([\\`*_|<>\[\]])", r"\\\1", text)
    return " ".join(escaped.split())


def generated_summary(path: Path) -> str | None:
    """The sentence a figure's rule writes beside it (``NAME_summary.json``, key ``summary``): the
    part of a caption that holds measured counts, so that no caption types them. Returned as
    reStructuredText (``rest_literal_text``)."""
    import json

    if not path.is_file():
        return None
    try:
        return rest_literal_text(str(json.loads(path.read_text())["summary"]))
    except (ValueError, KeyError):
        return None


def gallery_page(root: Path) -> str:
    """The gallery page's reStructuredText."""
    rules = figure_rules(root)
    lines = [".. This page is generated by docs/_ext/figure_gallery.py at every build: edit the captions in",
             "   workflow/report/ and the rules in workflow/rules/ instead.", "",
             ".. _gallery:", "", "Figure gallery", "==============", "",
             "Every figure the workflow draws, with the caption the Snakemake report shows (one source for",
             "both: ``workflow/report/``), the paper figure it reproduces, the rule and script that make it",
             "and, once built, what made it: the profile (quick or paper), commit and version stored in the",
             "PNG's provenance. A caption's values are those of that profile's configuration. Figures appear",
             "here after ``bash scripts/figures.sh`` has made them in this checkout; rebuild the site afterwards.", ""]
    for section in ("Main text", "Supplement", "Beyond the paper"):
        lines += [section, "-" * len(section), ""]
        for name in sorted(n for n in rules if section_of(n) == section):
            rule, script = rules[name]
            caption_file = root / "workflow" / "report" / f"{name}.rst"
            caption = caption_file.read_text() if caption_file.is_file() else "(no caption file)"
            png = root / "results" / "figures" / f"{name}.png"
            profile = recorded_profile(png) if png.is_file() else None
            caption = rendered_caption(caption, root, profile)
            lead = LEAD.search(caption)
            lines += [f".. _gallery-{name}:", "", name, "~" * len(name), ""]
            reproduces = lead.group(1).removeprefix("Paper ") if lead else "(not stated in the caption)"
            facts = [f"**Paper figure:** {reproduces}",
                     f"**Rule:** ``{rule}`` · **Script:** ``{script}``"]
            if png.is_file():
                facts.append(f"**Made by:** {profile_of(png)}")
                lines += [f".. image:: /../results/figures/{name}.png", f"   :alt: {name}", ""]
            else:
                facts.append(f"**Not built in this checkout.** Make it with ``bash scripts/figures.sh "
                             f"results/figures/{name}.png`` (paper scale: add ``--configfile config/paper.yaml``); "
                             "the caption's values are those of the default profile.")
            summary = generated_summary(root / "results" / "figures" / f"{name}_summary.json")
            if summary:
                facts.append(f"**In numbers (written by the rule):** {summary}")
            lines += [f"| {fact}" for fact in facts] + [""]
            lines += caption.splitlines() + [""]
    return "\n".join(lines) + "\n"


def write_gallery(app):
    root = Path(app.confdir).resolve().parent
    page = Path(app.srcdir) / "gallery.rst"
    text = gallery_page(root)
    # Rewritten only when it changed, so that an unchanged gallery does not rebuild the page.
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)


def setup(app):
    app.connect("builder-inited", write_gallery)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
