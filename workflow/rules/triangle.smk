# Triangular particles (supplement, Fig. S6): their catalogue of pre-made aggregates, the ansatz
# diagram at ell, and Monte Carlo snapshots. The same scripts as the hexagon's, with tiling="triangle".
# Names shared with other rules (TRIANGLE, TRIANGLE_MC, TRIANGLE_NU, file names) live in common.smk.

rule triangle_catalogue:
    output:
        "results/triangle/catalogue/ell{ell}_nu{nu}.npz",
    params:
        ell=lambda w: float(w.ell),
        nu=lambda w: float(w.nu),
        tiling="triangle",
        **pick(TRIANGLE, "eps", "method", "tol", "radius_per_ell", "width_per_ell", "min_radius", "min_width"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/triangle/catalogue_ell{ell}_nu{nu}.log",
    script:
        "../scripts/ansatz_catalogue.py"


rule triangle_diagram:
    input:
        lambda w: [triangle_catalogue_file(w.ell, nu) for nu in TRIANGLE_NU],
    output:
        "results/triangle/diagram_ell{ell}.npz",
    params:
        ell=lambda w: float(w.ell),
        nu=TRIANGLE_NU,
        **pick(TRIANGLE, "Gamma_max", "Gamma_count"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/triangle/diagram_ell{ell}.log",
    script:
        "../scripts/ansatz_diagram.py"


rule triangle_montecarlo_run:
    output:
        "results/triangle/runs/{kind}_nu{nu}_G{Gamma}.npz",
    params:
        nu=lambda w: float(w.nu),
        Gamma=lambda w: float(w.Gamma),
        seed=TRIANGLE_MC["seed"],
        kind=lambda w: w.kind,
        convention="measured",
        tiling="triangle",
        checkpoint_stem=lambda w: f"results/triangle/checkpoints/{w.kind}_nu{w.nu}_G{w.Gamma}",
        n=per_box(TRIANGLE_MC, "n"),
        box=per_box(TRIANGLE_MC, "box"),
        method=per_box(TRIANGLE_MC, "method"),
        sweeps=per_box(TRIANGLE_MC, "sweeps"),
        exchange={"rounds": 0},
        **pick(TRIANGLE_MC, "ell", "eps", "tol", "cluster_moves", "cluster_link", "bonded_moves", "surface_moves"),
    wildcard_constraints:
        kind="sparse|dense",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/triangle/{kind}_nu{nu}_G{Gamma}.log",
    benchmark:
        "results/benchmarks/triangle_montecarlo_run/{kind}_nu{nu}_G{Gamma}.tsv"
    script:
        "../scripts/montecarlo_run.py"


# Beyond the paper: the best single aggregate of as many triangles as each Monte Carlo box holds,
# which Fig. S6's snapshots are measured against (Delta E), as Fig. 3b's are.
rule triangle_finite_aggregates:
    output:
        "results/triangle/finite/n{n}_nu{nu}.npz",
    params:
        n=lambda w: int(w.n),
        nu=lambda w: float(w.nu),
        box=None,  # no box candidates on the triangle tiling
        tiling="triangle",
        **pick(TRIANGLE_MC, "ell", "eps"),
        **pick(MC, "finite_Gamma_count", "finite_Gamma_max", "finite_hole_fraction"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/triangle/finite_n{n}_nu{nu}.log",
    script:
        "../scripts/montecarlo_finite_aggregates.py"


rule triangle_shapes:
    output:
        "results/triangle/shapes.npz",
    params:
        ell=TRIANGLE["ell"],
        nu=TRIANGLE["drawing_nu"],
        eps=TRIANGLE["drawing_eps"],
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/triangle/shapes.log",
    script:
        "../scripts/triangle_shapes.py"


rule figS6_triangle:
    input:
        shapes=rules.triangle_shapes.output[0],
        diagram=f"results/triangle/diagram_ell{TRIANGLE['ell']:g}.npz",
        continuum=rules.continuum_phase_diagram.output,
        catalogue=triangle_catalogue_file(TRIANGLE["ell"], TRIANGLE["drawing_nu"]),
        snapshots=triangle_run_files(),
        finite=triangle_finite_files(),
    output:
        pdf=f"{FIGURES}/figS6_triangle.pdf",
        png=figure_png("figS6_triangle"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figS6_triangle.log",
    script:
        "../../figures/figS6_triangle.py"
