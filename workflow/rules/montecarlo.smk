# Monte Carlo annealing of aggregate topologies (Fig. 3b snapshots). One job per run; a run
# interrupted mid-way resumes from its checkpoint.
rule montecarlo_run:
    output:
        "results/montecarlo/runs/{kind}_nu{nu}_G{Gamma}_seed{seed}.npz",
    params:
        **mc_run_params(),
    # The anneal is serial; the replica exchange after it runs its replicas on this many threads
    # (raise it with --set-threads montecarlo_run=N where a job may have N cores).
    threads: 1
    wildcard_constraints:
        kind="sparse|dense|sparse_supplement|dense_supplement",
        seed=r"\d+",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/{kind}_nu{nu}_G{Gamma}_seed{seed}.log",
    # Per-rule cost tables (scripts/mc_rule_benchmarks.sh, docs/topics/montecarlo.md).
    benchmark:
        "results/benchmarks/montecarlo_run/{kind}_nu{nu}_G{Gamma}_seed{seed}.tsv"
    script:
        "../scripts/montecarlo_run.py"


# The large box's runs (figX_mc_scale, figX_mc_finite_size; issue 33, item 3): the same script
# with collective isometry moves and a schedule that dwells in the reshaping window
# (MC["large_collective"]), in a rule of their own so that the other kinds' params stay as they were.
use rule montecarlo_run as montecarlo_large_run with:
    params:
        **mc_run_params(),
        # Keys sorted: the same params whatever the order of the configuration file.
        collective=dict(sorted(MC["large_collective"].items())),
        # Its chain's relaxation options (parent_factor; MonteCarloOptions fields).
        relaxation=dict(sorted(MC["large_relaxation"].items())),
    wildcard_constraints:
        kind="large",
        seed=r"\d+",


rule montecarlo_diagram:
    input:
        runs=[mc_run_file(nu, G, MC["seeds"][0]) for nu in MC["diagram_nu"] for G in MC["diagram_Gamma"]],
        finite=[finite_aggregate_file(MC["n"], nu) for nu in MC["diagram_nu"]],
    output:
        "results/montecarlo/diagram.npz",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/diagram.log",
    script:
        "../scripts/montecarlo_diagram.py"


rule figX_mc_diagram:
    input:
        montecarlo=rules.montecarlo_diagram.output,
        diagram=f"results/ansatz/diagram_ell{ANSATZ['fig3b_ell']:g}.npz",
        continuum=rules.continuum_phase_diagram.output,
    output:
        pdf=f"{FIGURES}/figX_mc_diagram.pdf",
        png=figure_png("figX_mc_diagram"),
        # The runs in numbers (the caption's generated part; the gallery shows it under the caption).
        summary=report(f"{FIGURES}/figX_mc_diagram_summary.json", caption="../report/figX_mc_diagram_summary.rst",
                       category="Beyond the paper"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_mc_diagram.log",
    script:
        "../../figures/figX_mc_diagram.py"


# Beyond the paper: which single aggregate of n particles is best at each Gamma (the finite-size
# prediction for a Monte Carlo box of n particles), one job per (n, nu).
rule montecarlo_finite_aggregates:
    output:
        "results/montecarlo/finite/n{n}_nu{nu}.npz",
    params:
        n=lambda w: int(w.n),
        nu=lambda w: float(w.nu),
        # The box each particle number runs in (candidate ground states of that box).
        box=lambda w: {MC["n"]: MC["box"], MC["large_n"]: MC["large_box"], MC["dense_n"]: MC["dense_box"]}[int(w.n)],
        tiling="hexagon",
        **pick(MC, "ell", "eps", "finite_Gamma_count", "finite_Gamma_max", "finite_hole_fraction"),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/finite_n{n}_nu{nu}.log",
    script:
        "../scripts/montecarlo_finite_aggregates.py"


# Beyond the paper (issue: Monte Carlo at sizes where the diagram can be tested): Fig. 3b's line
# scans in the large box, every seed, each run against its box's predicted ground state.
rule montecarlo_scale:
    input:
        runs=mc_scale_files(),
        finite=sorted({finite_aggregate_file(MC["large_n"], nu) for _, nu, _ in mc_scale_points()}),
    output:
        "results/montecarlo/scale.npz",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/scale.log",
    script:
        "../scripts/montecarlo_diagram.py"


rule figX_mc_scale:
    input:
        scale=rules.montecarlo_scale.output,
        runs=mc_scale_files(),
    output:
        pdf=f"{FIGURES}/figX_mc_scale.pdf",
        png=figure_png("figX_mc_scale"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
        points=mc_scale_points(),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_mc_scale.log",
    script:
        "../../figures/figX_mc_scale.py"


rule figX_mc_finite_size:
    input:
        runs=mc_finite_size_files(),
        finite=finite_aggregate_files(),
    output:
        pdf=f"{FIGURES}/figX_mc_finite_size.pdf",
        png=figure_png("figX_mc_finite_size"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_mc_finite_size.log",
    script:
        "../../figures/figX_mc_finite_size.py"


# Beyond the paper (issue 33, item 1): single aggregates sampled at fixed size
# (pyfrustrate.montecarlo.fixed_size). Per point (scan, nu, Gamma): the ansatz's optimum, the
# sizes around it and the reshaping window's temperature; per size and seed one sample (a job of
# one core); validation.json gathers them.
rule montecarlo_validation_point:
    output:
        "results/montecarlo/validation/{scan}_nu{nu}_G{Gamma}/point.json",
    params:
        scan=lambda w: w.scan,
        nu=lambda w: float(w.nu),
        Gamma=lambda w: float(w.Gamma),
        steps=lambda w: VALIDATION[VALIDATION_STEPS[w.scan]],
        seed=VALIDATION["seeds"][0],
        **pick(MC, "ell", "eps"),
        **pick(VALIDATION, "method", "tol", "fibre_length", "disk_margin", "ansatz_max_width", "ansatz_max_radius",
               "window_temperatures", "window_sweeps", "window_max_excess", "window_min_acceptance",
               "bonded_moves", "surface_moves"),
    threads: 1
    wildcard_constraints:
        scan="fibre|disk",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/validation_{scan}_nu{nu}_G{Gamma}.log",
    benchmark:
        "results/benchmarks/montecarlo_validation_point/{scan}_nu{nu}_G{Gamma}.tsv"
    script:
        "../scripts/montecarlo_validation_point.py"


rule montecarlo_validation_sample:
    input:
        point="results/montecarlo/validation/{scan}_nu{nu}_G{Gamma}/point.json",
    output:
        "results/montecarlo/validation/{scan}_nu{nu}_G{Gamma}/size{index}_seed{seed}.json",
    params:
        index=lambda w: int(w.index),
        seed=lambda w: int(w.seed),
        **pick(VALIDATION, "method", "tol", "fibre_length", "disk_margin", "hold_sweeps", "cool_sweeps", "quench_sweeps",
               "bonded_moves", "surface_moves"),
    threads: 1
    wildcard_constraints:
        scan="fibre|disk",
        index=r"\d+",
        seed=r"\d+",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/validation_{scan}_nu{nu}_G{Gamma}_size{index}_seed{seed}.log",
    benchmark:
        "results/benchmarks/montecarlo_validation_sample/{scan}_nu{nu}_G{Gamma}_size{index}_seed{seed}.tsv"
    script:
        "../scripts/montecarlo_validation_sample.py"


# Issue 33, item 4: the ansatz's predicted state at a point against its nearest competitor
# (montecarlo.fixed_size.two_sided_seeds), held at the point's reshaping-window temperature.
rule montecarlo_validation_two_sided:
    input:
        point="results/montecarlo/validation/{scan}_nu{nu}_G{Gamma}/point.json",
    output:
        "results/montecarlo/validation/{scan}_nu{nu}_G{Gamma}/two_sided_{competitor}_seed{seed}.json",
    params:
        competitor=lambda w: w.competitor,
        seed=lambda w: int(w.seed),
        **pick(VALIDATION, "method", "tol", "fibre_length", "disk_margin", "hold_sweeps", "cool_sweeps",
               "quench_sweeps", "bonded_moves", "surface_moves"),
    threads: 1
    wildcard_constraints:
        scan="fibre|disk",
        competitor="two_disks|other_kind",
        seed=r"\d+",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/validation_{scan}_nu{nu}_G{Gamma}_two_sided_{competitor}_seed{seed}.log",
    benchmark:
        "results/benchmarks/montecarlo_validation_two_sided/{scan}_nu{nu}_G{Gamma}_{competitor}_seed{seed}.tsv"
    script:
        "../scripts/montecarlo_validation_two_sided.py"


# Issue 33, item 2: one fibre exchanging particles with a reservoir (outline moves,
# pyfrustrate.montecarlo.grand_canonical), seeded at the ansatz's best width and held at a
# temperature and at mu = min_W e(W) (the ansatz's threshold) + an offset; one job of one core each.
rule montecarlo_validation_grand:
    output:
        "results/montecarlo/validation/grand_nu{nu}_G{Gamma}/T{t}_mu{m}_seed{seed}.json",
    params:
        nu=lambda w: float(w.nu),
        Gamma=lambda w: float(w.Gamma),
        T_over_g=lambda w: GRAND["temperatures_over_g"][int(w.t)],
        mu_offset_over_g=lambda w: GRAND["mu_offsets_over_g"][int(w.m)],
        run_keys=lambda w: [int(w.t), int(w.m)],
        seed=lambda w: int(w.seed),
        **pick(MC, "ell", "eps"),
        **pick(VALIDATION, "method", "tol", "ansatz_max_width", "bonded_moves", "surface_moves"),
        **pick(GRAND, "length", "sweeps", "equilibration", "outline_moves"),
    threads: 1
    wildcard_constraints:
        t=r"\d+",
        m=r"\d+",
        seed=r"\d+",
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/validation_grand_nu{nu}_G{Gamma}_T{t}_mu{m}_seed{seed}.log",
    benchmark:
        "results/benchmarks/montecarlo_validation_grand/nu{nu}_G{Gamma}_T{t}_mu{m}_seed{seed}.tsv"
    script:
        "../scripts/montecarlo_validation_grand.py"


rule montecarlo_validation:
    input:
        points=[validation_point_file(*point) for point in validation_points()],
        samples=validation_sample_files(),
        two_sided=validation_two_sided_files(),
        grand=grand_sample_files(),
        scale=rules.montecarlo_scale.output,  # large_runs: the scale scans judged by structure
    output:
        "results/montecarlo/validation.json",
    params:
        large_points=mc_scale_points(),
        seeds=VALIDATION["seeds"],
        fibre_length=VALIDATION["fibre_length"],
        estimate_particles=VALIDATION["estimate_particles"],
        # The profile's whole scale, recorded in the file (keys sorted: the same params whatever
        # the order of the configuration file).
        scale=key_sorted(dict(VALIDATION, ell=MC["ell"], eps=MC["eps"])),
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/montecarlo/validation.log",
    script:
        "../scripts/montecarlo_validation.py"


rule figX_mc_validation:
    input:
        validation=rules.montecarlo_validation.output,
        points=[validation_point_file(*point) for point in validation_points()],
    output:
        pdf=f"{FIGURES}/figX_mc_validation.pdf",
        png=figure_png("figX_mc_validation"),
    params:
        profile=config["profile"],  # recorded in the figure's provenance
    conda:
        "../envs/pyfrustrate.yaml"
    log:
        "results/logs/figX_mc_validation.log",
    script:
        "../../figures/figX_mc_validation.py"
