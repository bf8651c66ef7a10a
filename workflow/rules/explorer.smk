# The interactive phase-diagram explorer (a static HTML page): the ansatz diagrams of Figs. 3b
# and S1 with each point's winning aggregate on hover. Linked from the documentation site.
rule explorer:
    input:
        diagrams=[f"results/ansatz/diagram_ell{ell:g}.npz" for ell in (ANSATZ["fig3b_ell"], ANSATZ["figS1_ell"])],
        # The catalogues each diagram was read from, in the same order (nu by nu, diagram by diagram).
        catalogues=[catalogue_file(ell, nu) for ell in (ANSATZ["fig3b_ell"], ANSATZ["figS1_ell"]) for nu in DIAGRAM_NU],
        continuum=rules.continuum_phase_diagram.output,
    output:
        "results/explorer/index.html",
    params:
        **pick(config["explorer"], "width", "height", "picture_inches", "picture_dpi", "periods"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/explorer.log",
    script:
        "../scripts/explorer.py"
