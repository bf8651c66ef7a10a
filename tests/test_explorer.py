"""The interactive phase-diagram explorer (rule ``explorer``): its script run on a small ansatz
diagram made by the workflow's own scripts, the page checked against the diagram it shows."""
import json
import re

import numpy as np
import pytest

pytest.importorskip("bokeh")

from script_jobs import Named, run_script  # noqa: E402

from pyfrustrate.io import load_npz  # noqa: E402

ELL, NUS, GAMMA_COUNT = 2.5, [0.3, 0.9], 5


@pytest.fixture(scope="module")
def explorer_page(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("explorer")
    catalogues = []
    for nu in NUS:  # small catalogues: disks up to radius 2, fibres up to width 2
        path = tmp / f"catalogue_nu{nu:g}.npz"
        run_script("workflow/scripts/ansatz_catalogue.py", "ansatz_catalogue", tmp, Named(), Named([str(path)]),
                   dict(ell=ELL, nu=nu, tiling="hexagon", eps=0.01, method="auto", tol=1e-5, radius_per_ell=0.1,
                        width_per_ell=0.1, min_radius=2, min_width=2))
        catalogues.append(str(path))
    diagram = tmp / "diagram.npz"
    run_script("workflow/scripts/ansatz_diagram.py", "ansatz_diagram", tmp, Named(catalogues), Named([str(diagram)]),
               dict(ell=ELL, nu=NUS, Gamma_max=1.6, Gamma_count=GAMMA_COUNT))
    continuum = tmp / "continuum.npz"
    run_script("workflow/scripts/continuum_phase_diagram.py", "continuum_phase_diagram", tmp, Named(),
               Named([str(continuum)]), dict(nu_count=11, Gamma_max=1.6, Gamma_count=17))
    page = tmp / "index.html"
    run_script("workflow/scripts/explorer.py", "explorer", tmp,
               Named(diagrams=[str(diagram)], catalogues=catalogues, continuum=[str(continuum)]), Named([str(page)]),
               dict(width=600, height=400, picture_inches=1.0, picture_dpi=30, periods=1))
    return page.read_text(), load_npz(diagram)


def _data_source(html):
    """The hover rows of the page's one data source (Bokeh embeds the document as JSON)."""
    documents = re.findall(r'<script type="application/json" id="[^"]+">\s*(.*?)\s*</script>', html, re.S)
    assert documents, "no embedded Bokeh document"
    text = json.dumps(json.loads(documents[0]))
    return text


def test_explorer_page_stands_alone_and_shows_every_point_of_the_diagram(explorer_page):
    html, diagram = explorer_page
    assert "cdn.bokeh.org" not in html  # JavaScript inline: the page reads offline
    document = _data_source(html)
    # One square per (nu, Gamma) point, each hover naming the point's winner as the diagram does.
    winners = {str(f) for f in np.asarray(diagram["family"]).ravel()}
    for family in winners:
        assert family in document, family
    # Each distinct winner's picture is embedded once, as a PNG data URI, under its own key.
    drawn = {f"nu{nu:g}_{f}_{int(s)}" for nu, fs, ss in zip(NUS, diagram["family"], diagram["size"])
             for f, s in zip(fs, ss)}
    for key in drawn:
        assert re.search(rf'"{key}",\s*"data:image/png;base64,', document), key  # a map entry [key, uri]
    assert len(re.findall(r'"data:image/png;base64,', document)) == len(drawn)
    assert f"ell = {ELL:g}" in html
